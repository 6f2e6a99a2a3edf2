// The initial global solution (steps 1-4 of PointlessMapper::Solve, pointless_mapper.h): the
// verified pairs, the focals from the view graph, the triplets, rotation and translation
// averaging with each triplet's global->local similarity. Their options and their result.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "averaging/global_init.h"
#include "averaging/outlier_injection.h"
#include "calibration/view_graph_calibration.h"
#include "pgba/io/json_config.h"
#include "pgba/io/report.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"
#include "triplets/triplet_options.h"
#include "triplets/pair_estimation.h"

namespace pgba {

// One options struct per stage, each read from the config section of the same name.
struct GlobalMapperOptions {
  PairOptions pairs;             // section "pairs"
  ViewGraphCalibrationOptions calibration;  // section "calibration"
  TripletOptions triplets;       // section "triplets"
  GlobalInitOptions global_init;  // section "global_init"
  // The paper's sensitivity experiment (outlier_injection.h): this fraction of the relative
  // rotations corrupted before step 4 averages them. Not a config key: `--rotation-outliers`
  // of `pgba init` / `pgba benchmark` and the benchmark's sweep set it.
  OutlierInjectionOptions rotation_outliers;

  // Empty if valid, else "section.key: problem" for the first invalid option.
  std::string Check() const;
};

// Adds the mapper's sections to a config schema / reads them from a loaded config (checked by
// ReadPointlessMapperOptions).
void AddGlobalMapperSections(ConfigSchema* schema);
void ReadGlobalMapperOptions(const Config& config, GlobalMapperOptions* options);

struct GlobalMapperResult {
  // The cameras the mapper ends with: the tracks' own, with the focals step 2 estimated.
  // Every later stage must use these (TracksWithCameras).
  std::map<uint32_t, Camera> cameras;
  ViewGraphCalibrationResult calibration;  // step 2 (empty when no camera was estimated)
  std::vector<TwoViewGeometry> pairs;
  GlobalInitResult init;  // poses, kept triplets with similarities, dropped images
  OutlierInjectionResult outliers_injected;  // with options.rotation_outliers: what was corrupted
};

// `tracks` with `cameras` in place of its own (a copy; the same ids are expected).
Reconstruction TracksWithCameras(const Reconstruction& tracks, const std::map<uint32_t, Camera>& cameras);

// True if `cameras` differ from the tracks' own in any parameter.
bool CamerasChanged(const Reconstruction& tracks, const std::map<uint32_t, Camera>& cameras);

}  // namespace pgba
