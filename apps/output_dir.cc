#include "apps/output_dir.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <system_error>

#include "pgba/util/atomic_file.h"
#include "pgba/util/error.h"

namespace pgba::app {
namespace fs = std::filesystem;

const std::vector<std::string> kFeaturesOutputs = {"features", "report.json"};
const std::vector<std::string> kMatchOutputs = {"tracks", "matching", "report.json"};
const std::vector<std::string> kInitOutputs = {"pairs.json", "triplets.json", "init",        "report.json",
                                               "fingerprint.json", "sparse", "points.ply", "report.html"};
const std::vector<std::string> kReconstructOutputs = {
    "sparse",        "points.ply", "report.json", "report.html",  "fingerprint.json",
    "pairs.json",    "triplets.json", "init",     "motions.json", "local_hessians.json"};
const std::vector<std::string> kRunOutputs = {
    "sparse",        "points.ply", "report.json", "report.html",  "fingerprint.json",   "pairs.json", "triplets.json",
    "init",          "motions.json", "local_hessians.json", "features", "tracks", "matching", "log.txt"};
const std::vector<std::string> kBenchmarkOutputs = {"models", "benchmark.json", "convergence.svg",
                                                    "outlier_sweep.svg"};
const std::vector<std::string> kMapperResults = {"sparse", "points.ply", "report.json", "report.html",
                                                 "fingerprint.json"};
const std::vector<std::string> kBenchmarkResults = kBenchmarkOutputs;

void CheckOutputDir(const std::string& out, const std::vector<std::string>& written,
                    const std::vector<NamedInput>& inputs) {
  RequireOutputPath(out, "--out");
  CheckOutputDirApartFromInputs(out, written, inputs);
}

void PrepareOutputDir(const std::string& out) {
  RemoveStaleStaging(out);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec || !fs::is_directory(out))
    ThrowInputError(out, 0, "cannot create the output folder" + (ec ? ": " + ec.message() : std::string()));
  const fs::path probe = fs::path(out) / (".pgba_write_probe." + std::to_string(::getpid()));
  {
    std::ofstream f(probe);
    if (!(f << "probe") || !f.flush()) ThrowInputError(out, 0, "output folder is not writable");
  }
  fs::remove(probe, ec);
}

void RemovePreviousResults(const std::string& out, const std::vector<std::string>& results) {
  std::error_code ec;
  // No folder there (or a file, which PrepareOutputDir reports): no earlier result.
  if (!fs::is_directory(out, ec)) return;
  for (const std::string& name : results) {
    fs::remove_all(fs::path(out) / name, ec);
    if (ec) ThrowInputError((fs::path(out) / name).string(), 0, "cannot remove the previous result: " + ec.message());
  }
}

void RecordFailure(const std::string& out, const std::exception& error, Report* report) {
  try {
    RemovePreviousResults(out);
  } catch (const std::exception&) {
    // The original error is the one to report.
  }
  (*report)["status"] = "failed";
  (*report)["error"] = error.what();
  try {
    report->Write((fs::path(out) / "report.json").string());
  } catch (const std::exception&) {
  }
}

WorkspaceFingerprint FingerprintOf(const Reconstruction& tracks, const PointlessMapperOptions& options,
                                   bool with_hessians) {
  WorkspaceFingerprint f;
  f.tracks = TracksFingerprint(tracks);
  f.init_options = WithoutThreadCounts({{"pairs", options.mapper.pairs},
                                        {"calibration", options.mapper.calibration},
                                        {"triplets", options.mapper.triplets},
                                        {"global_init", options.mapper.global_init}});
  if (with_hessians)
    f.hessian_options = WithoutThreadCounts(
        {{"local_motions", options.refinement.local_motions}, {"local_hessian", options.refinement.local_hessian}});
  return f;
}

}  // namespace pgba::app
