// The dataset layout `pgba run` and `pgba benchmark` read (shared/datasets/README.md):
//   OUT/images/        the photos (symbolic links to the originals, or copies)
//   OUT/cameras.txt    the calibration (COLMAP cameras.txt)
//   OUT/camera_map.txt "IMAGE_NAME CAMERA_ID" lines, only when there are several cameras
//   OUT/gt/            ground-truth poses, COLMAP text model with an empty points3D.txt
// Converters of public datasets (eth3d.h, tanks_and_temples.h) end here.
#pragma once

#include <map>
#include <string>
#include <vector>

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

// The entries WriteDatasetLayout writes in OUT (no input may be one of them or inside one).
extern const std::vector<std::string> kDatasetLayoutEntries;

// `gt` holds the cameras and the images (name = file name inside OUT/images/, pose);
// `sources` maps every image name of `gt` to the existing photo. Its points and 2D
// observations are not written. Before anything is written, what is written is checked as
// its readers check it (InputError naming the file): every camera (CheckCamera), every name
// (a plain file name that a COLMAP text model keeps, listed once), every photo present and
// of its camera's size (the header of a PNG or JPEG), and no photo inside an output entry
// (OUT/images being the photos' own folder replaced each photo by a link to itself). Outputs
// are written atomically (gt/ as a whole).
void WriteDatasetLayout(const Reconstruction& gt, const std::map<std::string, std::string>& sources,
                        const std::string& out, const DatasetLayoutOptions& options = {});

}  // namespace pgba
