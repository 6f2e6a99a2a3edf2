#include "modules/global_ba/global_ba_unknowns.h"

#include "modules/global_ba/global_ba_solve.h"

namespace pgba::internal {

std::map<uint32_t, Pose> CurrentPoses(const Unknowns& u) {
  std::map<uint32_t, Pose> poses;
  for (const auto& [id, block] : u.poses) poses[id] = block.ToPose();
  return poses;
}

MotionResidual* MakeResidual(const Unknowns& u, const MotionTerm& t) {
  std::vector<Eigen::Matrix3d> R0;
  for (const uint32_t id : t.hessian->image_ids) R0.push_back(u.poses.at(id).R0);
  return new MotionResidual(R0, t.sim, t.hessian->local_poses, t.W, t.newton_step, t.hessian->intrinsics0,
                            IntrinsicSizes(*t.hessian));
}

std::vector<double*> PoseBlocksOf(Unknowns& u, const MotionTerm& t) {
  std::vector<double*> blocks;
  for (const uint32_t id : t.hessian->image_ids) blocks.push_back(u.poses.at(id).x.data());
  return blocks;
}

std::vector<double*> IntrinsicBlocksOf(Unknowns& u, const MotionTerm& t) {
  std::vector<double*> blocks;
  for (const uint32_t id : t.hessian->intrinsic_camera_ids) blocks.push_back(u.intrinsics.at(id).x.data());
  return blocks;
}

}  // namespace pgba::internal
