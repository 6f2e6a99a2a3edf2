#include "pgba/io/trajectory_log.h"

#include <Eigen/Dense>
#include <cmath>
#include <iomanip>

#include "pgba/util/atomic_file.h"
#include "pgba/util/error.h"
#include "pgba/util/text_reader.h"

namespace pgba {

Pose TrajectoryFrame::ToPose() const {
  const Eigen::Matrix3d R_wc = camera_to_world.topLeftCorner<3, 3>();
  return Pose::FromRC(R_wc.transpose(), camera_to_world.topRightCorner<3, 1>());
}

TrajectoryFrame TrajectoryFrame::FromPose(const Pose& pose, const std::array<int64_t, 3>& header) {
  TrajectoryFrame f;
  f.header = header;
  f.camera_to_world.topLeftCorner<3, 3>() = pose.R().transpose();
  f.camera_to_world.topRightCorner<3, 1>() = pose.C();
  return f;
}

std::vector<TrajectoryFrame> ReadTrajectoryLog(const std::string& path) {
  TextReader reader(path);
  std::vector<TrajectoryFrame> frames;
  std::vector<std::string> tok;
  while (reader.NextLine(&tok)) {
    TrajectoryFrame f;
    f.line = reader.line_number();
    if (tok.size() != 3) reader.Fail("expected a frame header of 3 integers, got " + std::to_string(tok.size()) + " fields");
    for (int i = 0; i < 3; ++i) f.header[i] = reader.ToInt(tok[i], "frame header");
    for (int r = 0; r < 4; ++r) {
      if (!reader.NextLine(&tok)) reader.Fail("truncated frame: matrix row " + std::to_string(r + 1) + " of 4 missing");
      if (tok.size() != 4) reader.Fail("expected a matrix row of 4 numbers, got " + std::to_string(tok.size()) + " fields");
      for (int c = 0; c < 4; ++c) f.camera_to_world(r, c) = reader.ToDouble(tok[c], "matrix entry");
    }
    if (f.camera_to_world.row(3) != Eigen::RowVector4d(0, 0, 0, 1))
      reader.Fail("last matrix row must be 0 0 0 1 (a rigid camera-to-world transform)");
    const Eigen::Matrix3d R = f.camera_to_world.topLeftCorner<3, 3>();
    if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-4 || R.determinant() < 0)
      ThrowInputError(path, f.line, "the frame's 3x3 block is not a rotation (scaled or reflected transform)");
    frames.push_back(f);
  }
  return frames;
}

void WriteTrajectoryLog(const std::vector<TrajectoryFrame>& frames, const std::string& path) {
  WriteFileAtomically(path, [&](std::ostream& out) {
    out << std::setprecision(17);
    for (const TrajectoryFrame& f : frames) {
      out << f.header[0] << ' ' << f.header[1] << ' ' << f.header[2] << '\n';
      for (int r = 0; r < 4; ++r)
        out << f.camera_to_world(r, 0) << ' ' << f.camera_to_world(r, 1) << ' ' << f.camera_to_world(r, 2) << ' '
            << f.camera_to_world(r, 3) << '\n';
    }
  });
}

}  // namespace pgba
