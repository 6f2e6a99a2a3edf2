// The evaluation stage: one model judged by the metrics every method shares
// (ARCHITECTURE.md): sigma on the observation model's tracks, pose errors against ground
// truth, loop-closure error on withheld correspondences. `pgba evaluate` and `benchmark`
// call Evaluate; the JSON key names are the report keys scripts read.
#pragma once

#include <string>

#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <vector>

#include "evaluation/ground_truth.h"
#include "evaluation/loop_closure.h"
#include "evaluation/sigma.h"
#include "pgba/scene/reconstruction.h"

namespace pgba {

struct EvaluationOptions {
  SigmaOptions sigma;
  GroundTruthOptions ground_truth;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(EvaluationOptions, sigma, ground_truth)

struct EvaluationMetrics {
  size_t images_input = 0;       // images of the observation model
  size_t images_registered = 0;  // of those, present (by name) in the evaluated model
  SigmaResult sigma;
  std::optional<GroundTruthErrors> ground_truth;  // when a GT model was given
  std::optional<LoopClosureResult> loop;          // when loop correspondences were given

  // Flat object with the keys of docs/formats.md, "Reports" (images_input, images_registered, sigma_rms,
  // sigma_median, inlier_fraction, rot_err_deg_median, rot_err_deg_max,
  // center_err_rel_median, center_err_rel_max, loop_err_rms, loop_err_median); a key is
  // absent when its metric is not computable. Supporting counts go under "details".
  nlohmann::json ToJson() const;
  // Human-readable table under `title` (one metric per row, "n/a" where not computable).
  void PrintTable(std::ostream& out, const std::string& title = "evaluation") const;
};

// `model`: the evaluated poses (and intrinsics); `obs`: the observations and tracks (e.g.
// the input model), matched to `model` by image name; `gt` and `loops` optional.
EvaluationMetrics Evaluate(const Reconstruction& model, const Reconstruction& obs, const Reconstruction* gt,
                           const std::vector<LoopCorrespondence>* loops, const EvaluationOptions& options = {});

}  // namespace pgba
