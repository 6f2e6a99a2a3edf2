// Adds one stage record to WS/report.json, keeping what other stages wrote there (features
// and match run as separate processes, so each reads, merges and rewrites the file).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace pgba::app {

// report["stages"][stage] = record (replacing an earlier record of the same stage); the file
// is created if absent and written atomically. A report.json that is not valid JSON is
// replaced, with a warning.
void MergeStageIntoReport(const std::string& report_path, const std::string& stage, const nlohmann::json& record);

// Before a stage re-runs: its record (and `outputs`, paths it writes) removed, so that a
// failed re-run leaves nothing that reads as its result (the next stage would use it).
// Stale staging of a killed run below `workspace` is removed too (atomic_file.h).
void ForgetStage(const std::string& workspace, const std::string& stage, const std::vector<std::string>& outputs);

}  // namespace pgba::app
