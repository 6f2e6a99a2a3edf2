// A relative motion of N >= 3 views (paper section 3): their poses in a local frame of their
// own, the tracks their local BA uses, and the frame's global->local similarity (paper eq. 4).
// The triplets of the initialisation are the paper's case N = 3; eqs. 1-5 hold for any N (the
// local Hessian is then 6N x 6N), and longer motions carry the information that triplets
// chained along a sequence lose (local_hessian/local_motions.h). One type for every N: the
// triplet stage makes motions of three views, the local Hessian stage takes any.
#pragma once

#include <cstdint>
#include <vector>

#include "pgba/geometry/pose.h"
#include "pgba/geometry/sim3.h"
#include "pgba/geometry/triangulation.h"

namespace pgba {

struct LocalMotion {
  // The views; a triplet's (triplets/triplets.h) ascending.
  std::vector<uint32_t> image_ids;
  // World(local)->camera poses of the views in the motion's local frame, same order.
  std::vector<Pose> local_poses;
  // Tracks (point3D ids of the input model) of the motion's local BA; the local Hessian stage
  // uses exactly these.
  std::vector<uint64_t> track_ids;
  // Global->local similarity X_loc = s R X + t (paper eq. 4; filled by the averaging stage
  // for triplets, by the global BA's start for other motions).
  Sim3 global_to_local;
  // Reprojection RMS (pixels) after the motion's own BA (the triplet BA); 0 when not solved.
  double rms_px = 0.0;
  // Optional start of the triangulation of each track (aligned with track_ids, in the local
  // frame; empty or a non-finite entry: none): the points of the motion's previous local
  // Hessian, carried into the next re-linearisation (TriangulateTrackFrom).
  std::vector<PointStart> track_points;

  int num_views() const { return static_cast<int>(image_ids.size()); }
};

// No image twice among the motion's views (a malformed or hostile input can repeat one).
inline bool HasDistinctImages(const LocalMotion& motion) {
  for (size_t a = 0; a < motion.image_ids.size(); ++a)
    for (size_t b = a + 1; b < motion.image_ids.size(); ++b)
      if (motion.image_ids[a] == motion.image_ids[b]) return false;
  return true;
}

}  // namespace pgba
