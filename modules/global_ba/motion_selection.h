// Which motions enter the global BA: those with a usable local Hessian and initial poses
// for all their images, restricted to the largest rigidly connected component (two motions
// are linked when they share two images: sharing one image leaves their relative scale
// free, so separate components would each carry their own gauge).
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "modules/local_hessian/local_hessian.h"
#include "pgba/geometry/pose.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

struct MotionSelection {
  std::vector<int> hessian_indices;  // into `hessians`, ascending
  std::vector<uint32_t> images;      // covered by the selected motions, ascending
  int num_excluded = 0;              // ok-or-not hessians left out
  std::vector<uint32_t> excluded_images;  // initial poses not covered
};

// Throws InputError if a hessian does not match its motion (index out of range, other
// image ids, or two hessians for one motion) or an initial pose is not finite.
MotionSelection SelectMotions(const std::map<uint32_t, Pose>& initial_poses, const std::vector<LocalMotion>& motions,
                              const std::vector<LocalHessian>& hessians);

}  // namespace pgba
