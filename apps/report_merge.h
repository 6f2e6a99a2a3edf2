// Adds one stage record to WS/report.json, keeping what other stages wrote there (features
// and match run as separate processes, so each reads, merges and rewrites the file).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace pgba::app {

// report["stages"][stage] = record (replacing an earlier record of the same stage); the file
// is created if absent and written atomically. A report.json that is not valid JSON is
// replaced, with a warning.
void MergeStageIntoReport(const std::string& report_path, const std::string& stage, const nlohmann::json& record);

}  // namespace pgba::app
