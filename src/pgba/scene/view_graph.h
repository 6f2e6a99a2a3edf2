// Artefacts of global initialisation that later stages consume: verified image pairs with
// their relative pose, triplets with their local poses (consistent scale inside the
// triplet), and each triplet's global->local similarity (paper eq. 4).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "pgba/geometry/pose.h"
#include "pgba/geometry/sim3.h"
#include "pgba/geometry/triangulation.h"

namespace pgba {

// Relative geometry of a pair: x_2 = R_21 x_1 + t_21 with |t_21| = 1 (camera frames).
struct TwoViewGeometry {
  uint32_t image_id1 = 0;
  uint32_t image_id2 = 0;
  Eigen::Matrix3d R_21 = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t_21 = Eigen::Vector3d::UnitX();
  int num_tracks = 0;   // tracks shared by the two images
  int num_inliers = 0;  // of the essential-matrix fit
  double median_triangulation_angle_deg = 0.0;
};

// Three views with poses in a local frame of the triplet (scale consistent over the three).
struct Triplet {
  std::array<uint32_t, 3> image_ids{};
  // World(local)->camera poses of the three views in the triplet's local frame.
  std::array<Pose, 3> local_poses;
  // Tracks (point3D ids of the input model) used by the triplet BA; the local Hessian
  // stage uses exactly these.
  std::vector<uint64_t> track_ids;
  double rms_px = 0.0;  // reprojection RMS after the triplet BA
  // Global->local similarity X_loc = s R X + t (filled by the averaging stage).
  Sim3 global_to_local;
};

// A relative motion of N >= 3 views (paper section 3): their poses in a local frame of their
// own, the tracks their local BA uses, and the frame's global->local similarity. The
// triplets are the paper's case N = 3; eqs. 1-5 hold for any N (the local Hessian is then
// 6N x 6N), and longer motions carry the information that triplets chained along a
// sequence lose (local_motions.h).
struct LocalMotion {
  std::vector<uint32_t> image_ids;
  std::vector<Pose> local_poses;  // world(local)->camera, same order as image_ids
  std::vector<uint64_t> track_ids;
  Sim3 global_to_local;
  // Optional start of the triangulation of each track (aligned with track_ids, in the local
  // frame; empty or a non-finite entry: none): the points of the motion's previous local
  // Hessian, carried into the next re-linearisation (TriangulateTrackFrom).
  std::vector<PointStart> track_points;

  LocalMotion() = default;
  // A triplet is the motion of its three views (implicit: wherever a motion is expected).
  LocalMotion(const Triplet& t)  // NOLINT(google-explicit-constructor)
      : image_ids(t.image_ids.begin(), t.image_ids.end()),
        local_poses(t.local_poses.begin(), t.local_poses.end()),
        track_ids(t.track_ids),
        global_to_local(t.global_to_local) {}

  int num_views() const { return static_cast<int>(image_ids.size()); }
};

inline std::vector<LocalMotion> MotionsOfTriplets(const std::vector<Triplet>& triplets) {
  return {triplets.begin(), triplets.end()};
}

}  // namespace pgba
