// The dataset layout `pgba run` and `pgba benchmark` read (shared/datasets/README.md):
//   OUT/images/        the photos (symbolic links to the originals, or copies)
//   OUT/cameras.txt    the calibration (COLMAP cameras.txt)
//   OUT/camera_map.txt "IMAGE_NAME CAMERA_ID" lines, only when there are several cameras
//   OUT/gt/            ground-truth poses, COLMAP text model with an empty points3D.txt
// Converters of public datasets (eth3d.h, tanks_and_temples.h) end here.
#pragma once

#include <map>
#include <string>

#include "pgba/scene/reconstruction.h"

namespace pgba {

struct DatasetLayoutOptions {
  // Copy the photos instead of linking them (links keep the originals' space; copies survive
  // moving or deleting the download).
  bool copy_images = false;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};

// `gt` holds the cameras and the images (name = file name inside OUT/images/, pose);
// `sources` maps every image name of `gt` to the existing photo. Its points and 2D
// observations are not written. InputError naming the file if a source is missing or a
// name is not a plain file name; outputs are written atomically (gt/ as a whole).
void WriteDatasetLayout(const Reconstruction& gt, const std::map<std::string, std::string>& sources,
                        const std::string& out, const DatasetLayoutOptions& options = {});

}  // namespace pgba
