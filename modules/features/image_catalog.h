// Which files of an image folder are photos, and which calibrated camera each one uses.
//
// Calibration is a COLMAP cameras.txt. How images map to cameras:
//   - one camera in the file: every image uses it;
//   - several cameras: a camera map is required, a text file of lines "IMAGE_NAME CAMERA_ID"
//     ('#' comments allowed); an image absent from the map is skipped with a warning.
// Without an explicit calibration path, DIR/cameras.txt and then DIR/../cameras.txt are
// tried (the layout of the datasets in shared/datasets).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "pgba/scene/camera.h"

namespace pgba {

struct CalibrationInput {
  std::string cameras_path;     // "" = look next to the images (see above)
  std::string camera_map_path;  // "" = none (only valid with a single camera)
};

struct ImageCatalog {
  std::map<uint32_t, Camera> cameras;
  std::string cameras_path;  // the calibration file actually used
  // File name (relative to the folder) -> camera id, for the files that have a camera.
  std::map<std::string, uint32_t> camera_of;
  // Every visible regular file of the folder, sorted by name (images or not: the decoder
  // decides later, so that a non-image gets a warning naming it).
  std::vector<std::string> files;
};

// Lists DIR (not recursive; hidden files are ignored) and resolves the calibration. Errors
// that stop the run (InputError): DIR missing or without files, no calibration found, an
// unreadable calibration or camera map, several cameras without a map, a map naming an
// unknown camera.
ImageCatalog BuildImageCatalog(const std::string& images_dir, const CalibrationInput& calibration);

}  // namespace pgba
