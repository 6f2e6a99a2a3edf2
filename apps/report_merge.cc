#include "apps/report_merge.h"

#include <filesystem>

#include "pgba/util/atomic_file.h"
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

}  // namespace pgba::app
