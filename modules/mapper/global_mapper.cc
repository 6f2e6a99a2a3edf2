#include "mapper/global_mapper.h"


namespace pgba {

void AddGlobalMapperSections(ConfigSchema* schema) {
  const GlobalMapperOptions defaults;
  schema->Add("pairs", defaults.pairs)
      .Add("calibration", defaults.calibration)
      .Add("triplets", defaults.triplets)
      .Add("global_init", defaults.global_init);
}

std::string GlobalMapperOptions::Check() const {
  if (const std::string p = pairs.Check(); !p.empty()) return "pairs." + p;
  if (const std::string p = calibration.Check(); !p.empty()) return "calibration." + p;
  if (const std::string p = triplets.Check(); !p.empty()) return "triplets." + p;
  if (const std::string p = global_init.Check(); !p.empty()) return "global_init." + p;
  if (const std::string p = rotation_outliers.Check(); !p.empty()) return "rotation_outliers." + p;
  return "";
}

void ReadGlobalMapperOptions(const Config& config, GlobalMapperOptions* options) {
  ReadSection(config, "pairs", &options->pairs);
  ReadSection(config, "calibration", &options->calibration);
  ReadSection(config, "triplets", &options->triplets);
  ReadSection(config, "global_init", &options->global_init);
}

Reconstruction TracksWithCameras(const Reconstruction& tracks, const std::map<uint32_t, Camera>& cameras) {
  Reconstruction out = tracks;
  out.cameras = cameras;
  return out;
}

bool CamerasChanged(const Reconstruction& tracks, const std::map<uint32_t, Camera>& cameras) {
  if (cameras.size() != tracks.cameras.size()) return true;
  for (const auto& [id, cam] : tracks.cameras) {
    const auto it = cameras.find(id);
    if (it == cameras.end() || it->second.model != cam.model || it->second.params != cam.params) return true;
  }
  return false;
}

}  // namespace pgba
