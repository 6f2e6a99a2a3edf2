// The global->local similarity of each triplet after averaging (paper eq. 4; the estimator,
// FitMotionSimilarity in pgba/geometry/sim3.h, says how: the rotation from the camera
// rotations, the scale and translation by least squares on the centres), with the residuals
// that decide whether the triplet agrees with the averaged poses.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <vector>

#include "pgba/geometry/pose.h"
#include "pgba/geometry/sim3.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

// alpha = proj_SO(3)( sum_k r_k^T R_k ), R_k from `rotations` (all three must be present).
Eigen::Matrix3d AverageTripletRotation(const LocalMotion& triplet, const std::map<uint32_t, Eigen::Matrix3d>& rotations);

struct TripletSimilarityFit {
  bool valid = false;  // false: coincident global centres or a non-positive scale
  Sim3 global_to_local;
  // max_k angle(r_k, R_k alpha^T), degrees.
  double rotation_residual_deg = 0.0;
  // RMS_k |c_k - (lambda alpha C_k + beta)| / RMS_k |c_k - c_bar|: the centre misfit relative
  // to the triplet's local size.
  double centre_residual_rel = 0.0;
};

// Fits the similarity of one triplet to the global poses of its views (all three present).
TripletSimilarityFit EstimateTripletSimilarity(const LocalMotion& triplet, const std::map<uint32_t, Pose>& poses);

// Fits every triplet in parallel and stores each valid similarity in
// LocalMotion::global_to_local. Returns the fits in the order of `triplets`.
std::vector<TripletSimilarityFit> ComputeTripletSimilarities(const std::map<uint32_t, Pose>& poses,
                                                             std::vector<LocalMotion>* triplets);

}  // namespace pgba
