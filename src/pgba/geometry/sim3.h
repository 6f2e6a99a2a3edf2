// 3D similarity Y = s R X + t, and its estimation from point correspondences (Umeyama,
// through Eigen::umeyama).
//
// Applied to a camera pose (ARCHITECTURE.md, paper eq. 4): a similarity d mapping the
// global frame to a local one sends centre C to c = s R C + t and rotation R_cam to
// R_cam R^T (the camera sees the same directions).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "pgba/geometry/pose.h"

namespace pgba {

struct Sim3 {
  double s = 1.0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();

  Eigen::Vector3d Apply(const Eigen::Vector3d& X) const { return s * (R * X) + t; }
  Pose Apply(const Pose& pose) const;
  Sim3 Inverse() const;
  // (a * b)(X) = a(b(X)).
  Sim3 operator*(const Sim3& b) const;
  Eigen::Matrix4d Matrix() const;
};

// Least-squares similarity with dst ~ Apply(src) (Umeyama 1991). Returns false for fewer than
// 3 correspondences or (nearly) collinear / coincident source points.
bool EstimateSim3(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst,
                  Sim3* sim);

// The global->local similarity of a relative motion (paper eq. 4, ARCHITECTURE.md convention)
//     c_k = lambda alpha C_k + beta,   r_k = R_k alpha^T,
// fitted to the global poses (R_k, C_k) and the local poses (r_k, c_k) of its N views. The
// rotation comes from the camera rotations, not from the centres: r_k = R_k alpha^T gives
// alpha = r_k^T R_k for each view, and alpha is the projection onto SO(3) of their mean (the
// chordal L2 mean); the centres of a motion are often nearly collinear (video, aerial strips,
// a triplet) and would leave the rotation about their line undetermined. With alpha fixed,
// lambda and beta are the linear least-squares fit of the centres (Umeyama's scale and
// translation with the rotation given):
//     lambda = sum_k <c_k - c_bar, alpha (C_k - C_bar)> / sum_k |alpha (C_k - C_bar)|^2,
//     beta   = c_bar - lambda alpha C_bar.
// The one estimator of this similarity: the triplets' after averaging (averaging/similarity.h)
// and a motion's start in the global BA (global_ba/motion_similarity.h).
struct MotionSimilarityFit {
  Eigen::Matrix3d alpha = Eigen::Matrix3d::Identity();
  // 0 when the global centres coincide; a fit whose lambda is not positive and finite has no
  // usable scale (scale_ok).
  double lambda = 0.0;
  Eigen::Vector3d global_centroid = Eigen::Vector3d::Zero();  // C_bar
  Eigen::Vector3d local_centroid = Eigen::Vector3d::Zero();   // c_bar
  bool scale_ok() const;
  Sim3 ToSim3() const;
};
// `global` and `local`: the N views' poses in the same order (N >= 1).
MotionSimilarityFit FitMotionSimilarity(const std::vector<Pose>& global, const std::vector<Pose>& local);
// Its rotation alone, from the views' global and local camera rotations (same order):
// alpha = proj_SO(3)(sum_k r_k^T R_k).
Eigen::Matrix3d MotionRotation(const std::vector<Eigen::Matrix3d>& global_R, const std::vector<Eigen::Matrix3d>& local_R);
// The mean of the poses' centres (zero for none).
Eigen::Vector3d MeanCentre(const std::vector<Pose>& poses);

}  // namespace pgba
