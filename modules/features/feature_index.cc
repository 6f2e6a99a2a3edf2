#include "features/feature_index.h"

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "pgba/io/colmap_text.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/util/atomic_file.h"
#include "pgba/util/error.h"

namespace pgba {
namespace fs = std::filesystem;

std::string FeaturesDir(const std::string& workspace) { return (fs::path(workspace) / "features").string(); }

std::string FeatureFilePath(const std::string& workspace, const std::string& image_name) {
  return (fs::path(FeaturesDir(workspace)) / (image_name + ".bin")).string();
}

void WriteFeatureIndex(const std::string& workspace, const FeatureIndex& index) {
  fs::create_directories(FeaturesDir(workspace));
  Reconstruction rec;
  rec.cameras = index.cameras;
  WriteColmapCamerasFile(rec, (fs::path(FeaturesDir(workspace)) / "cameras.txt").string());
  nlohmann::json images = nlohmann::json::array();
  for (const IndexedImage& im : index.images)
    images.push_back({{"image_id", im.image_id},
                      {"name", im.name},
                      {"camera_id", im.camera_id},
                      {"width", im.width},
                      {"height", im.height},
                      {"num_features", im.num_features},
                      {"detection_scale", im.detection_scale}});
  WriteStringAtomically(fs::path(FeaturesDir(workspace)) / "images.json",
                        nlohmann::json{{"version", 1}, {"images", images}}.dump(1) + "\n");
}

FeatureIndex ReadFeatureIndex(const std::string& workspace) {
  const fs::path json_path = fs::path(FeaturesDir(workspace)) / "images.json";
  const fs::path cams_path = fs::path(FeaturesDir(workspace)) / "cameras.txt";
  if (!fs::is_regular_file(json_path) || !fs::is_regular_file(cams_path))
    ThrowInputError(json_path.string(), 0, "no feature index in the workspace: run `pgba features` first");
  FeatureIndex index;
  index.cameras = ReadColmapCameras(cams_path.string());
  std::ifstream in(json_path);
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    for (const nlohmann::json& e : j.at("images")) {
      IndexedImage im;
      im.image_id = e.at("image_id").get<uint32_t>();
      im.name = e.at("name").get<std::string>();
      im.camera_id = e.at("camera_id").get<uint32_t>();
      im.width = e.at("width").get<int>();
      im.height = e.at("height").get<int>();
      im.num_features = e.at("num_features").get<int>();
      im.detection_scale = e.value("detection_scale", 1.0);
      if (!index.cameras.count(im.camera_id))
        ThrowInputError(json_path.string(), 0,
                        "image " + im.name + " uses unknown camera " + std::to_string(im.camera_id));
      index.images.push_back(std::move(im));
    }
  } catch (const nlohmann::json::exception& e) {
    ThrowInputError(json_path.string(), 0, std::string("malformed feature index: ") + e.what());
  }
  return index;
}

}  // namespace pgba
