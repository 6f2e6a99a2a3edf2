// The output folder of the commands that write a result (init, reconstruct, run,
// benchmark): checked before any work, and cleared of the previous run's results so that a
// failed run leaves nothing that reads as its result.
#pragma once

#include <string>

#include "mapper/pointless_mapper.h"
#include "pgba/io/workspace_fingerprint.h"

namespace pgba::app {

// Creates `out` and probes that a file can be written in it: a bad --out (a file, no
// permission, a read-only file system) is an InputError now, not after the computation.
void PrepareOutputDir(const std::string& out);

// Removes the results of an earlier run in `out`: sparse/, points.ply, report.json,
// report.html, the workspace fingerprint (the workspace artefacts beside it are rewritten by
// this run; until then they are refused as a --workspace). Cached inputs (features/, tracks/)
// stay: a re-run resumes from them.
void RemovePreviousResults(const std::string& out);

// The fingerprint of a workspace computed from `tracks` with `options` (its hessian part
// only if the workspace holds local hessians).
WorkspaceFingerprint FingerprintOf(const Reconstruction& tracks, const PointlessMapperOptions& options,
                                   bool with_hessians);

}  // namespace pgba::app
