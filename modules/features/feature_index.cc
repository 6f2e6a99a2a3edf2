#include "features/feature_index.h"

#include <filesystem>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <set>

#include "pgba/io/colmap_text.h"
#include "pgba/io/json_file_reader.h"
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
  std::error_code ec;
  if (!fs::exists(json_path, ec) || !fs::exists(cams_path, ec))
    ThrowInputError(json_path.string(), 0, "no feature index in the workspace: run `pgba features` first");
  FeatureIndex index;
  index.cameras = ReadColmapCameras(cams_path.string());
  // Strictly, as every JSON input (a FIFO refused, duplicate keys and 1e999 named), and each
  // value in its domain: an image id or a size the matching would take on trust.
  const JsonFileReader reader(json_path.string());
  const nlohmann::json j = reader.Parse();
  const nlohmann::json& images = reader.Field(j, "images", "");
  if (!images.is_array()) reader.Fail("images", "expected an array");
  std::set<uint32_t> ids;
  std::set<std::string> names;
  for (const nlohmann::json& e : images) {
    const std::string where = "images[" + std::to_string(index.images.size()) + "]";
    auto integer = [&](const char* key, int64_t lo, int64_t hi) {
      const int64_t v = reader.Integer(reader.Field(e, key, where), where + "." + key);
      if (v < lo || v > hi)
        reader.Fail(where + "." + key, std::to_string(v) + " is out of range [" + std::to_string(lo) + ", " +
                                           std::to_string(hi) + "]");
      return v;
    };
    IndexedImage im;
    im.image_id = static_cast<uint32_t>(integer("image_id", 0, UINT32_MAX));
    const nlohmann::json& name = reader.Field(e, "name", where);
    if (!name.is_string() || name.get<std::string>().empty()) reader.Fail(where + ".name", "expected a file name");
    im.name = name.get<std::string>();
    im.camera_id = static_cast<uint32_t>(integer("camera_id", 0, UINT32_MAX));
    im.width = static_cast<int>(integer("width", 1, INT32_MAX));
    im.height = static_cast<int>(integer("height", 1, INT32_MAX));
    im.num_features = static_cast<int>(integer("num_features", 0, INT32_MAX));
    if (e.is_object() && e.contains("detection_scale")) {
      im.detection_scale = reader.Number(e["detection_scale"], where + ".detection_scale");
      if (!(im.detection_scale > 0)) reader.Fail(where + ".detection_scale", "must be > 0");
    }
    if (!index.cameras.count(im.camera_id))
      reader.Fail(where, "image " + im.name + " uses unknown camera " + std::to_string(im.camera_id));
    if (!ids.insert(im.image_id).second) reader.Fail(where, "image_id " + std::to_string(im.image_id) + " listed twice");
    if (!names.insert(im.name).second) reader.Fail(where, "image " + im.name + " listed twice");
    if (!index.images.empty() && im.image_id < index.images.back().image_id)
      reader.Fail(where, "images are not sorted by image_id");
    index.images.push_back(std::move(im));
  }
  return index;
}

}  // namespace pgba
