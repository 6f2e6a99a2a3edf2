// PLY export of a reconstruction for viewers (MeshLab, CloudCompare): the 3D points with
// their colours, followed by the camera centres in one distinct colour so that the camera
// path stands out. Vertices only (no faces); coordinates as doubles so that georeferenced
// scenes keep their precision. Written atomically.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "pgba/scene/reconstruction.h"

namespace pgba {

struct PlyOptions {
  // binary_little_endian (compact, fast) or ascii (readable, diffable).
  bool binary = true;
  // Append one vertex per image at its camera centre.
  bool camera_centers = true;
  // Colour of the camera-centre vertices (magenta: rare in real scenes).
  Eigen::Matrix<uint8_t, 3, 1> camera_color = Eigen::Matrix<uint8_t, 3, 1>(255, 0, 255);
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};

// Vertices: points3D in id order, then (if enabled) camera centres in image-id order.
// The header carries "comment pgba points N cameras M" so a reader can split them.
void WritePly(const Reconstruction& rec, const std::string& path, const PlyOptions& options = {});

}  // namespace pgba
