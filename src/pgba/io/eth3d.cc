#include "pgba/io/eth3d.h"

#include <filesystem>
#include <map>

#include "pgba/io/colmap_text.h"
#include "pgba/util/error.h"
#include "pgba/util/text_reader.h"

namespace pgba {

namespace fs = std::filesystem;

namespace {

fs::path Under(const std::string& scene, const std::string& p) {
  return fs::path(p).is_absolute() ? fs::path(p) : fs::path(scene) / p;
}

// Before the COLMAP reader (which knows more models than ETH3D needs): only undistorted
// pinhole cameras are ground truth we can use as they are.
void RequirePinholeCameras(const std::string& cameras_path) {
  TextReader reader(cameras_path);
  std::vector<std::string> tok;
  while (reader.NextLine(&tok)) {
    if (tok.size() < 2) continue;  // the COLMAP reader reports truncated lines
    if (tok[1] != "PINHOLE" && tok[1] != "SIMPLE_PINHOLE")
      reader.Fail("camera model " + TextReader::Printable(tok[1]) +
                  " is not supported: use ETH3D's undistorted variant (dslr_calibration_undistorted/ with "
                  "images/dslr_images_undistorted/, PINHOLE cameras)");
  }
}

// The ground truth with image names reduced to file names; `originals` gets each image's
// name as given (relative to the images root).
Reconstruction ReadGroundTruth(const std::string& scene_dir, const Eth3dOptions& options,
                               std::map<uint32_t, std::string>* originals) {
  const fs::path calib = Under(scene_dir, options.calibration_dir);
  RequirePinholeCameras((calib / "cameras.txt").string());
  Reconstruction rec = ReadColmapText(calib.string(), /*points_optional=*/true);
  rec.points3D.clear();
  std::map<std::string, std::string> first;
  for (auto& [id, im] : rec.images) {
    const std::string name = fs::path(im.name).filename().string();
    const auto [it, fresh] = first.emplace(name, im.name);
    if (!fresh)
      ThrowInputError((calib / "images.txt").string(), 0, "images '" + it->second + "' and '" + im.name +
                       "' have the same file name");
    (*originals)[id] = im.name;
    im.name = name;
    im.points2D.clear();
  }
  return rec;
}

}  // namespace

Reconstruction ReadEth3dGroundTruth(const std::string& scene_dir, const Eth3dOptions& options) {
  std::map<uint32_t, std::string> originals;
  return ReadGroundTruth(scene_dir, options, &originals);
}

size_t ConvertEth3dScene(const std::string& scene_dir, const std::string& out, const Eth3dOptions& options) {
  std::map<uint32_t, std::string> originals;
  const Reconstruction gt = ReadGroundTruth(scene_dir, options, &originals);
  const fs::path root = Under(scene_dir, options.images_root);
  std::map<std::string, std::string> sources;
  for (const auto& [id, im] : gt.images) sources[im.name] = (root / originals.at(id)).string();
  WriteDatasetLayout(gt, sources, out, options.layout);
  return gt.images.size();
}

}  // namespace pgba
