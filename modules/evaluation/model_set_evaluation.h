// The evaluation of a reconstruction of several models (one per component of the view
// graph): each model judged on its own by Evaluate (evaluation.h), with its own similarity to
// the ground truth, and the rotation errors of every model's images together.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "evaluation/evaluation.h"
#include "pgba/scene/reconstruction.h"

namespace pgba {

struct ModelSetEvaluation {
  std::vector<EvaluationMetrics> models;  // in the order of the models
  size_t images_input = 0;
  size_t images_registered = 0;  // over every model
  // Per image of every model that the ground truth holds (model by model, each in its own
  // alignment): name, model index and rotation error.
  std::vector<std::string> names;
  std::vector<int> model_of;
  std::vector<double> rot_err_deg;
  double rot_err_deg_median = 0.0, rot_err_deg_max = 0.0;

  // {"images_input", "images_registered", "models": n, "rot_err_deg_median", "rot_err_deg_max"
  // (with ground truth)}.
  nlohmann::json ToJson() const;
};

// Every model against `gt` (may be null), its sigma on the observations `obs`.
ModelSetEvaluation EvaluateModelSet(const std::vector<const Reconstruction*>& models, const Reconstruction& obs,
                                    const Reconstruction* gt, const EvaluationOptions& options = {});

}  // namespace pgba
