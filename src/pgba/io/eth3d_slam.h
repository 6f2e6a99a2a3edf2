// ETH3D SLAM sequences (https://www.eth3d.net/slam_datasets; the paper's "planar_mono") into
// the dataset layout (dataset_layout.h). A sequence folder holds, in the TUM RGB-D format,
//   rgb/<timestamp>.png          the frames
//   rgb.txt                      "timestamp rgb/<file>" per frame
//   calibration.txt              "fx fy cx cy" (PINHOLE, undistorted)
//   groundtruth.txt              "timestamp tx ty tz qx qy qz qw": camera-to-world, i.e. the
//                                camera centre and the rotation camera -> world
// Frames are matched to ground-truth lines by timestamp (nearest within max_dt_s); frames
// without ground truth are left out with a warning. The image size (needed by cameras.txt)
// is read from the first frame's PNG header.
#pragma once

#include <string>

#include "pgba/io/dataset_layout.h"
#include "pgba/scene/reconstruction.h"

namespace pgba {

struct Eth3dSlamOptions {
  // Largest |t_frame - t_groundtruth| accepted when pairing (seconds).
  double max_dt_s = 0.005;
  DatasetLayoutOptions layout;
};

// The ground-truth model of a sequence (names = the frames' file names). InputError naming
// the file and line for malformed input, or if no frame has ground truth.
Reconstruction ReadEth3dSlamGroundTruth(const std::string& sequence_dir, const Eth3dSlamOptions& options = {});

// ReadEth3dSlamGroundTruth + WriteDatasetLayout into `out`. Returns the number of images.
size_t ConvertEth3dSlamSequence(const std::string& sequence_dir, const std::string& out,
                                const Eth3dSlamOptions& options = {});

}  // namespace pgba
