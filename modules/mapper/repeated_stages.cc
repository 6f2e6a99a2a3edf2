#include "mapper/repeated_stages.h"

#include <string>

namespace pgba {

void RenameStages(Report* report, std::initializer_list<const char*> names, const std::string& suffix) {
  nlohmann::json& stages = (*report)["stages"];
  for (const char* name : names)
    if (stages.contains(name)) {
      stages[std::string(name) + suffix] = stages[name];
      stages.erase(name);
    }
}

void KeepFirstAdjustmentStages(Report* report) {
  RenameStages(report,
               {"local_hessians", "local_hessians_output", "global_ba", "gcp_check", "convergence", "verification",
                "triangulation", "more_models", "local_hessians_before_readjustment",
                "local_hessians_output_before_readjustment", "global_ba_before_readjustment",
                "verification_before_readjustment", "local_hessians_before_triplet_start",
                "local_hessians_output_before_triplet_start", "global_ba_before_triplet_start"},
               "_before_joining");
}

}  // namespace pgba
