// The trajectory ".log" format of Tanks and Temples (and the Redwood / Open3D tools): per
// frame one header line of 3 integers (in T&T's files: frame id, frame id, 0) followed by 4
// lines of the 4x4 camera-to-world matrix [R_wc | C ; 0 0 0 1] (x_world = R_wc x_cam + C).
// Blank lines and '#' comments are skipped.
//
// Reading is strict: a header that is not 3 integers, a matrix row that is not 4 finite
// numbers, a last row other than 0 0 0 1 or a rotation block that is not a rotation (to
// 1e-4) is an InputError "FILE:LINE: problem".
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "pgba/geometry/pose.h"

namespace pgba {

struct TrajectoryFrame {
  std::array<int64_t, 3> header{};
  Eigen::Matrix4d camera_to_world = Eigen::Matrix4d::Identity();
  int line = 0;  // of the header, for messages

  // Our convention (ARCHITECTURE.md): world->camera R = R_wc^T, centre C.
  Pose ToPose() const;
  static TrajectoryFrame FromPose(const Pose& pose, const std::array<int64_t, 3>& header);
};

std::vector<TrajectoryFrame> ReadTrajectoryLog(const std::string& path);

// 17 significant digits, atomically.
void WriteTrajectoryLog(const std::vector<TrajectoryFrame>& frames, const std::string& path);

}  // namespace pgba
