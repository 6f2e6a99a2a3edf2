#include "pgba/io/calibration_json.h"

#include <nlohmann/json.hpp>

#include "pgba/io/input_checks.h"
#include "pgba/io/json_file_reader.h"

namespace pgba {

CalibrationFile ReadCalibrationJson(const std::string& path) {
  const JsonFileReader r(path);
  const nlohmann::json doc = r.Parse();
  const nlohmann::json& cameras = r.Field(doc, "cameras", "");
  if (!cameras.is_array() || cameras.empty()) r.Fail("cameras", "expected a non-empty array of cameras");
  CalibrationFile out;
  for (size_t k = 0; k < cameras.size(); ++k) {
    const nlohmann::json& c = cameras[k];
    const std::string where = "cameras[" + std::to_string(k) + "]";
    Camera cam;
    const int64_t id = r.Integer(r.Field(c, "camera_id", where), where + ".camera_id");
    if (id < 0 || id > UINT32_MAX) r.Fail(where, "camera_id out of range");
    cam.camera_id = static_cast<uint32_t>(id);
    const nlohmann::json& model = r.Field(c, "model", where);
    if (!model.is_string() || !ParseCameraModel(model.get<std::string>(), &cam.model))
      r.Fail(where, "unknown camera model " + model.dump());
    const int64_t width = r.Integer(r.Field(c, "width", where), where + ".width");
    const int64_t height = r.Integer(r.Field(c, "height", where), where + ".height");
    if (width <= 0 || height <= 0 || width > 1000000 || height > 1000000) r.Fail(where, "image size out of range");
    cam.width = static_cast<int>(width);
    cam.height = static_cast<int>(height);
    const nlohmann::json& params = r.Field(c, "params", where);
    if (!params.is_array()) r.Fail(where, "\"params\" must be an array of numbers");
    for (const nlohmann::json& p : params) {
      if (!p.is_number()) r.Fail(where, "\"params\" must be an array of numbers, got " + p.dump());
      cam.params.push_back(p.get<double>());
    }
    const std::string problem = CheckCamera(cam);
    if (!problem.empty()) r.Fail(where, problem);
    if (!out.cameras.emplace(cam.camera_id, cam).second) r.Fail(where, "camera_id " + std::to_string(id) + " listed twice");
  }
  if (doc.contains("images")) {
    const nlohmann::json& images = doc.at("images");
    if (!images.is_object()) r.Fail("images", "expected an object {\"IMAGE_NAME\": CAMERA_ID, ...}");
    for (const auto& [name, id_json] : images.items()) {
      const int64_t id = r.Integer(id_json, "images." + name);
      if (id < 0 || id > static_cast<int64_t>(UINT32_MAX) || !out.cameras.count(static_cast<uint32_t>(id)))
        r.Fail("images." + name, "camera " + std::to_string(id) + " is not in \"cameras\"");
      out.camera_of[name] = static_cast<uint32_t>(id);
    }
  }
  return out;
}

}  // namespace pgba
