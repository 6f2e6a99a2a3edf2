#include "features/image_catalog.h"

#include <algorithm>
#include <filesystem>

#include "pgba/io/colmap_text.h"
#include "pgba/util/error.h"
#include "pgba/util/text_reader.h"

namespace pgba {
namespace fs = std::filesystem;

namespace {

std::string FindCalibration(const fs::path& dir, const std::string& given) {
  if (!given.empty()) {
    if (!fs::is_regular_file(given)) ThrowInputError(given, 0, "calibration file not found");
    return given;
  }
  for (const fs::path& p : {dir / "cameras.txt", dir.parent_path() / "cameras.txt"})
    if (fs::is_regular_file(p)) return p.string();
  ThrowInputError(dir.string(), 0,
                  "no calibration: pass --calib cameras.txt (looked for cameras.txt in the folder and its parent)");
}

std::map<std::string, uint32_t> ReadCameraMap(const std::string& path, const std::map<uint32_t, Camera>& cameras) {
  std::map<std::string, uint32_t> map;
  TextReader reader(path);
  std::vector<std::string> tokens;
  while (reader.NextLine(&tokens)) {
    reader.RequireTokens(tokens, 2, "IMAGE_NAME CAMERA_ID");
    const int64_t id = reader.ToInt(tokens[1], "CAMERA_ID");
    if (!cameras.count(static_cast<uint32_t>(id)) || id < 0)
      reader.Fail("camera " + tokens[1] + " is not in the calibration");
    if (!map.emplace(tokens[0], static_cast<uint32_t>(id)).second) reader.Fail("image " + tokens[0] + " listed twice");
  }
  return map;
}

}  // namespace

ImageCatalog BuildImageCatalog(const std::string& images_dir, const CalibrationInput& calibration) {
  if (!fs::is_directory(images_dir)) ThrowInputError(images_dir, 0, "image folder not found");
  const fs::path dir = fs::weakly_canonical(images_dir);  // no trailing '/': parent_path() is the parent
  ImageCatalog catalog;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.empty() || name[0] == '.' || !e.is_regular_file()) continue;
    catalog.files.push_back(name);
  }
  std::sort(catalog.files.begin(), catalog.files.end());
  if (catalog.files.empty()) ThrowInputError(images_dir, 0, "image folder is empty");

  catalog.cameras_path = FindCalibration(dir, calibration.cameras_path);
  catalog.cameras = ReadColmapCameras(catalog.cameras_path);
  if (catalog.cameras.empty()) ThrowInputError(catalog.cameras_path, 0, "calibration has no camera");
  for (const auto& [id, cam] : catalog.cameras) {
    const std::string problem = cam.Validate();
    if (!problem.empty()) ThrowInputError(catalog.cameras_path, 0, "camera " + std::to_string(id) + ": " + problem);
  }

  if (!calibration.camera_map_path.empty()) {
    catalog.camera_of = ReadCameraMap(calibration.camera_map_path, catalog.cameras);
  } else if (catalog.cameras.size() == 1) {
    for (const std::string& f : catalog.files) catalog.camera_of[f] = catalog.cameras.begin()->first;
  } else {
    ThrowInputError(catalog.cameras_path, 0,
                    std::to_string(catalog.cameras.size()) +
                        " cameras: pass a camera map (lines \"IMAGE_NAME CAMERA_ID\") to say which image uses which");
  }
  return catalog;
}

}  // namespace pgba
