// Pose errors against ground truth (ARCHITECTURE.md, "Evaluation metrics").
//
// The evaluated model lives in an arbitrary similarity frame, so its camera centres are
// first Sim(3)-aligned to the true centres (Umeyama, EstimateSim3). The alignment is made
// robust to a few badly placed cameras, which would otherwise tilt it and smear their
// error over every image: align on all common images, drop those whose centre error
// exceeds `outlier_factor` x the median error, re-align on the rest, and repeat until the
// kept set no longer changes (at most `max_rounds`). Errors are then reported for EVERY
// common image, including the dropped ones, under the final alignment S = (s, A, t):
//   rotation error (deg) = angle(R_est A^T, R_gt)      (the aligned camera rotation),
//   centre error (rel.)  = ||s A C_est + t - C_gt|| / extent,
// where the scene extent is the largest distance between two ground-truth camera centres
// (over all images of the ground-truth model, so that it does not depend on how many images
// a method registered, and is invariant to the GT frame's rotation).
//
// Beside these, gauge-free relative errors over every pair (i, j) of common images, which no
// alignment enters (a Sim(3) fit on nearly collinear centres, a strip or a street, can tilt
// every aligned rotation and so misreport them):
//   relative rotation error (deg)  = angle(R_j R_i^T, R*_j R*_i^T),
//   translation direction error (deg) = angle between R_i (C_j - C_i) and R*_i (C*_j - C*_i),
// the direction of camera j's centre seen from camera i (the relative translation's
// direction, scale-free).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pgba/geometry/sim3.h"
#include "pgba/scene/reconstruction.h"

namespace pgba {

struct GroundTruthOptions {
  // Centres with an alignment error above this multiple of the median error are left out of
  // the re-estimated alignment (their errors are still reported).
  double outlier_factor = 5.0;
  // Re-alignment rounds.
  int max_rounds = 3;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(GroundTruthOptions, outlier_factor, max_rounds)

struct GroundTruthErrors {
  // False when fewer than 3 images are common to both models or their true centres are
  // (nearly) collinear: the similarity, hence every error, is then undefined.
  bool ok = false;
  size_t num_common = 0;            // images present (by name) in both models
  size_t num_alignment_inliers = 0;  // images used by the final alignment
  Sim3 alignment;                   // evaluated frame -> ground-truth frame
  double collinearity = 0.0;  // second / first singular value of the centred true centres
  double scene_extent = 0.0;        // largest distance between two GT centres
  // Per common image, in the evaluated model's image-id order.
  std::vector<std::string> names;
  std::vector<double> rot_err_deg;
  std::vector<double> center_err_rel;
  double rot_err_deg_median = 0.0, rot_err_deg_max = 0.0;
  double center_err_rel_median = 0.0, center_err_rel_max = 0.0;
  // Gauge-free errors over all pairs of common images (0 pairs for fewer than 2 images).
  size_t num_pairs = 0;
  double rel_rot_err_deg_median = 0.0, rel_rot_err_deg_max = 0.0;
  double rel_dir_err_deg_median = 0.0, rel_dir_err_deg_max = 0.0;
};

// The relative errors of GroundTruthErrors between two pose lists of the same images (same
// order): median and max over all pairs. Fills num_pairs and the rel_* fields of `out`.
void RelativePoseErrors(const std::vector<Pose>& est, const std::vector<Pose>& truth, GroundTruthErrors* out);

// Largest distance between two camera centres of `rec` (0 for fewer than two images).
double SceneExtent(const Reconstruction& rec);

GroundTruthErrors CompareToGroundTruth(const Reconstruction& model, const Reconstruction& gt,
                                       const GroundTruthOptions& options = {});

}  // namespace pgba
