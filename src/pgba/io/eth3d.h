// ETH3D high-resolution multi-view scenes (https://www.eth3d.net/datasets) into the dataset
// layout (dataset_layout.h). A scene of the "undistorted" DSLR archives looks like
//   SCENE/images/dslr_images_undistorted/DSC_0286.JPG ...
//   SCENE/dslr_calibration_undistorted/{cameras.txt, images.txt, points3D.txt}
// where the calibration is a COLMAP text model (PINHOLE cameras; image names relative to
// SCENE/images/). Its poses are the laser-scan-aligned ground truth (metres); its points
// and 2D observations are COLMAP's own and are not ground truth, so they are dropped.
// The distorted variant (dslr_calibration_jpg/, THIN_PRISM_FISHEYE cameras) is rejected:
// pgba's camera models do not include the fisheye model.
#pragma once

#include <string>

#include "pgba/io/dataset_layout.h"
#include "pgba/scene/reconstruction.h"

namespace pgba {

struct Eth3dOptions {
  // The calibration folder, relative to the scene (or absolute).
  std::string calibration_dir = "dslr_calibration_undistorted";
  // Where the image names of images.txt are rooted, relative to the scene (or absolute).
  std::string images_root = "images";
  DatasetLayoutOptions layout;
};

// Reads SCENE/<calibration_dir> (InputError naming the file and line for a camera model
// other than PINHOLE / SIMPLE_PINHOLE, or two images with the same file name) and returns
// the ground truth with image names reduced to their file names.
Reconstruction ReadEth3dGroundTruth(const std::string& scene_dir, const Eth3dOptions& options = {});

// ReadEth3dGroundTruth + WriteDatasetLayout into `out`. Returns the number of images.
size_t ConvertEth3dScene(const std::string& scene_dir, const std::string& out, const Eth3dOptions& options = {});

}  // namespace pgba
