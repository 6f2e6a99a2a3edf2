// Which files of an image folder are photos, and which calibrated camera each one uses.
//
// Calibration is a COLMAP cameras.txt, or a .json file (pgba/io/calibration_json.h: the same
// cameras, optionally with the image -> camera map inside). How images map to cameras:
//   - one camera in the file: every image uses it;
//   - several cameras: a camera map is required, a text file of lines "IMAGE_NAME CAMERA_ID"
//     ('#' comments allowed) or the JSON file's "images"; an image absent from the map is
//     skipped with a warning.
// Without an explicit calibration path, DIR/cameras.txt and then DIR/../cameras.txt are
// tried (the layout of the datasets in shared/datasets).
// Without any calibration file, the cameras are priors, as COLMAP makes them: every image is
// decoded for its size and gets a SIMPLE_RADIAL camera (k = 0) with f = its EXIF focal
// (exif_focal.h; 1.2 * max(width, height) without a usable one, then
// Camera::has_prior_focal_length is false and the global mapper estimates the focal from
// the view graph) and the principal point at the image centre; images of the same size and
// focal share a camera, and each camera gets one warning line.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "features/feature_index.h"
#include "pgba/scene/camera.h"

namespace pgba {

struct CalibrationInput {
  std::string cameras_path;     // "" = look next to the images (see above)
  std::string camera_map_path;  // "" = none (only valid with a single camera)
};

struct ImageCatalog {
  std::map<uint32_t, Camera> cameras;
  std::string cameras_path;  // the calibration file actually used; "" for EXIF priors
  // "file: PATH", or for priors "exif" / "default-prior" / "exif+default-prior" (some
  // cameras from EXIF, some on the default).
  std::string calibration_source;
  // File name (relative to the folder) -> camera id, for the files that have a camera.
  std::map<std::string, uint32_t> camera_of;
  // Every visible regular file of the folder, sorted by name (images or not: the decoder
  // decides later, so that a non-image gets a warning naming it). Left out, each with a
  // warning naming it: entries that cannot be stat'ed (symlink loop) and truncated JPEGs.
  std::vector<std::string> files;
};

// Lists DIR (not recursive; hidden files are ignored) and resolves the calibration. Errors
// that stop the run (InputError): DIR missing or without files, an unreadable calibration or
// camera map, several cameras without a map, a map naming an unknown camera, a camera map
// without a calibration file, no calibration file and no decodable image.
// With priors, files that do not decode are given camera 1, so that the features stage
// skips them with its usual reason ("not an image file", ...), as with a calibration file.
ImageCatalog BuildImageCatalog(const std::string& images_dir, const CalibrationInput& calibration);

}  // namespace pgba
