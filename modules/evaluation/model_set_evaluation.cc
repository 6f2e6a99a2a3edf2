#include "evaluation/model_set_evaluation.h"

#include <algorithm>

namespace pgba {

nlohmann::json ModelSetEvaluation::ToJson() const {
  nlohmann::json j = {{"images_input", images_input}, {"images_registered", images_registered},
                      {"models", models.size()}};
  if (!rot_err_deg.empty()) {
    j["rot_err_deg_median"] = rot_err_deg_median;
    j["rot_err_deg_max"] = rot_err_deg_max;
  }
  return j;
}

ModelSetEvaluation EvaluateModelSet(const std::vector<const Reconstruction*>& models, const Reconstruction& obs,
                                    const Reconstruction* gt, const EvaluationOptions& options) {
  ModelSetEvaluation e;
  e.images_input = obs.images.size();
  for (size_t m = 0; m < models.size(); ++m) {
    e.models.push_back(Evaluate(*models[m], obs, gt, nullptr, options));
    const EvaluationMetrics& metrics = e.models.back();
    e.images_registered += metrics.images_registered;
    if (!metrics.ground_truth || !metrics.ground_truth->ok) continue;
    const GroundTruthErrors& g = *metrics.ground_truth;
    for (size_t i = 0; i < g.names.size(); ++i) {
      e.names.push_back(g.names[i]);
      e.model_of.push_back(static_cast<int>(m));
      e.rot_err_deg.push_back(g.rot_err_deg[i]);
    }
  }
  if (!e.rot_err_deg.empty()) {
    std::vector<double> sorted = e.rot_err_deg;
    std::sort(sorted.begin(), sorted.end());
    e.rot_err_deg_median = sorted[sorted.size() / 2];
    e.rot_err_deg_max = sorted.back();
  }
  return e;
}

}  // namespace pgba
