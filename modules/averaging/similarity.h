// The global->local similarity of each triplet (paper eq. 4, ARCHITECTURE.md convention):
//     X_loc = lambda alpha X + beta,   c_k = lambda alpha C_k + beta,   r_k = R_k alpha^T,
// given the global poses (R_k, C_k) of its three views and its local poses (r_k, c_k).
//
// The rotation comes from the camera rotations, not from the centres: r_k = R_k alpha^T
// gives alpha = r_k^T R_k for each view, and alpha is the projection onto SO(3) of their
// mean (the chordal L2 mean). Three centres of a triplet are often nearly collinear (video,
// aerial strips) and would leave the rotation about their line undetermined (ARCHITECTURE.md,
// numerical lessons). With alpha fixed, lambda and beta are the linear least-squares fit of
// the centres (Umeyama's scale and translation with the rotation given):
//     lambda = sum_k <c_k - c_bar, alpha (C_k - C_bar)> / sum_k |C_k - C_bar|^2,
//     beta   = c_bar - lambda alpha C_bar.
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
Eigen::Matrix3d AverageTripletRotation(const Triplet& triplet, const std::map<uint32_t, Eigen::Matrix3d>& rotations);

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
TripletSimilarityFit EstimateTripletSimilarity(const Triplet& triplet, const std::map<uint32_t, Pose>& poses);

// Fits every triplet in parallel and stores each valid similarity in
// Triplet::global_to_local. Returns the fits in the order of `triplets`.
std::vector<TripletSimilarityFit> ComputeTripletSimilarities(const std::map<uint32_t, Pose>& poses,
                                                             std::vector<Triplet>* triplets);

}  // namespace pgba
