#include "pgba/io/report.h"

#include "pgba/util/atomic_file.h"

namespace pgba {

nlohmann::json& Report::AddStage(const std::string& name, double seconds, double cpu_seconds, double peak_rss_mb) {
  nlohmann::json& stages = root_["stages"];
  if (stages.is_null()) stages = nlohmann::json::object();
  const size_t order = stages.contains(name) ? stages[name].value("order", stages.size()) : stages.size();
  nlohmann::json& stage = stages[name];
  stage = nlohmann::json::object();
  stage["seconds"] = seconds;
  if (cpu_seconds >= 0) {
    stage["cpu_seconds"] = cpu_seconds;
    stage["load_average"] = NumberOrNull(LoadAverage1Min());
  }
  stage["peak_rss_mb"] = peak_rss_mb >= 0 ? peak_rss_mb : PeakRssMb();
  stage["rss_mb"] = CurrentRssMb();
  stage["order"] = order;
  root_["peak_rss_mb"] = ProcessPeakRssMb();
  return stage;
}

void Report::Write(const std::string& path) const { WriteStringAtomically(path, root_.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n"); }

nlohmann::json& StageTimer::Stop() {
  stopped_ = true;
  return report_->AddStage(name_, timer_.Seconds(), cpu_timer_.Seconds(), memory_.PeakMb());
}

}  // namespace pgba
