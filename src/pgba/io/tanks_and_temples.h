// Tanks and Temples scenes (https://www.tanksandtemples.org/download/) into the dataset layout
// (dataset_layout.h). A training scene ships its images (SCENE/*.jpg, video frames) and the
// reference camera trajectory SCENE_COLMAP_SfM.log (trajectory_log.h: camera-to-world
// matrices, one per image in file-name order); it ships no intrinsics, so a COLMAP
// cameras.txt with one camera is given separately (e.g. from a COLMAP run on the images,
// see datasets/README.md).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "pgba/io/dataset_layout.h"
#include "pgba/io/trajectory_log.h"
#include "pgba/scene/reconstruction.h"

namespace pgba {

// The ground-truth model: image i (id i + 1) named names[i] with the pose of frames[i],
// all on the single camera of `cameras`. InputError naming `log_path` if the counts differ
// or `cameras` does not hold exactly one camera.
Reconstruction TrajectoryToModel(const std::vector<TrajectoryFrame>& frames, const std::vector<std::string>& names,
                                 const std::map<uint32_t, Camera>& cameras, const std::string& log_path);

struct TanksAndTemplesInput {
  std::string log_path;      // SCENE_COLMAP_SfM.log
  std::string images_dir;    // the scene's photos
  std::string cameras_path;  // COLMAP cameras.txt, one camera
  // Optional text file of image names (one per line, '#' comments), in the order of the
  // log's frames; default: the photos of images_dir (.jpg/.jpeg/.png, any case) sorted by name.
  std::string image_list;
};

// Reads the inputs, TrajectoryToModel, WriteDatasetLayout into `out`. Returns the number of
// images.
size_t ConvertTanksAndTemples(const TanksAndTemplesInput& input, const std::string& out,
                              const DatasetLayoutOptions& layout = {});

}  // namespace pgba
