#include "apps/report_merge.h"

#include <filesystem>

#include "pgba/util/atomic_file.h"
#include "pgba/util/error.h"
#include "pgba/util/input_file.h"
#include "pgba/util/logging.h"

namespace pgba::app {

void MergeStageIntoReport(const std::string& report_path, const std::string& stage, const nlohmann::json& record) {
  nlohmann::json report = nlohmann::json::object();
  if (std::filesystem::exists(report_path)) {
    report = nlohmann::json::parse(ReadRegularFile(report_path), nullptr, /*allow_exceptions=*/false);
    if (report.is_discarded() || !report.is_object()) {
      PGBA_LOG_WARN << report_path << ": not a JSON object; rewriting it";
      report = nlohmann::json::object();
    }
  }
  report["stages"][stage] = record;
  WriteStringAtomically(report_path, report.dump(2) + "\n");
}

void ForgetStage(const std::string& workspace, const std::string& stage, const std::vector<std::string>& outputs) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(workspace, ec)) return;
  RemoveStaleStaging(workspace);
  for (const std::string& output : outputs) {
    const fs::path p = fs::path(workspace) / output;
    fs::remove_all(p, ec);
    if (ec) ThrowInputError(p.string(), 0, "cannot remove the previous result: " + ec.message());
  }
  const std::string report_path = (fs::path(workspace) / "report.json").string();
  if (!fs::is_regular_file(report_path, ec)) return;
  nlohmann::json report = nlohmann::json::parse(ReadRegularFile(report_path), nullptr, /*allow_exceptions=*/false);
  if (report.is_discarded() || !report.is_object() || !report.contains("stages") || !report["stages"].is_object() ||
      !report["stages"].contains(stage))
    return;
  report["stages"].erase(stage);
  WriteStringAtomically(report_path, report.dump(2) + "\n");
}

}  // namespace pgba::app
