// The output folder of the commands that write a result (init, reconstruct, run,
// benchmark): checked before any work, and cleared of the previous run's results so that a
// failed run leaves nothing that reads as its result.
#pragma once

#include <exception>
#include <string>
#include <vector>

#include "mapper/pointless_mapper.h"
#include "pgba/io/report.h"
#include "pgba/io/workspace_fingerprint.h"
#include "pgba/util/output_path.h"

namespace pgba::app {

// The entries each command writes or removes in its output folder (the inputs of a command
// must not be, or lie inside, one of them).
extern const std::vector<std::string> kFeaturesOutputs;
extern const std::vector<std::string> kMatchOutputs;
extern const std::vector<std::string> kInitOutputs;
extern const std::vector<std::string> kReconstructOutputs;
extern const std::vector<std::string> kRunOutputs;
extern const std::vector<std::string> kBenchmarkOutputs;

// Before anything is touched: `out` (the --out of the command) is not empty and is apart from
// every input (util/output_path.h). InputError "OUT: problem" otherwise.
void CheckOutputDir(const std::string& out, const std::vector<std::string>& written,
                    const std::vector<NamedInput>& inputs);

// Creates `out` and probes that a file can be written in it: a bad --out (a file, no
// permission, a read-only file system) is an InputError now, not after the computation.
void PrepareOutputDir(const std::string& out);

// The entries of `out` that read as a command's result. Of init, reconstruct and run:
// sparse/, points.ply, report.json, report.html and the workspace fingerprint (the workspace
// artefacts beside it are rewritten by the next run; without the fingerprint they are refused
// as a --workspace). Of benchmark: benchmark.json, models/ and the plots. Cached inputs
// (features/, tracks/) are not results: a re-run resumes from them.
extern const std::vector<std::string> kMapperResults;
extern const std::vector<std::string> kBenchmarkResults;

// Removes the `results` of an earlier run in `out`: first thing in a command, so that a
// re-run refused at its options or inputs does not leave the earlier result.
void RemovePreviousResults(const std::string& out, const std::vector<std::string>& results = kMapperResults);

// After a failure (of the computation or of a write: a full disk): the results written so
// far removed (RemovePreviousResults) and report.json written with status "failed" and the
// error, as far as the disk allows (a full disk may refuse even that; nothing then reads as a
// result).
void RecordFailure(const std::string& out, const std::exception& error, Report* report);

// The fingerprint of a workspace computed from `tracks` with `options` (its hessian part
// only if the workspace holds local hessians).
WorkspaceFingerprint FingerprintOf(const Reconstruction& tracks, const PointlessMapperOptions& options,
                                   bool with_hessians);

}  // namespace pgba::app
