// The global mapper: the pipeline from tracks to an initial global solution, reading like
// the paper's steps 2 (relative motions and initial global solution):
//   1. verified pairs (from the image front end's geometries where `pgba run` has them)
//   2. focals from the view graph for the cameras without a prior focal (modules/calibration;
//      section "calibration", "cameras": "none" skips it); if a focal changed, the pairs
//      are verified again with it
//   3. triplets (+ triplet BA) -> rotation averaging -> translation averaging -> per-triplet
//      global->local similarities.
// `pgba init` runs it and writes the workspace; `reconstruct` and `benchmark` continue from
// its result in the same process.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "averaging/global_init.h"
#include "calibration/view_graph_calibration.h"
#include "pgba/io/json_config.h"
#include "pgba/io/report.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"
#include "triplets/triplet_options.h"
#include "triplets/view_graph.h"

namespace pgba {

// One options struct per stage, each read from the config section of the same name.
struct GlobalMapperOptions {
  PairOptions pairs;             // section "pairs"
  ViewGraphCalibrationOptions calibration;  // section "calibration"
  TripletOptions triplets;       // section "triplets"
  GlobalInitOptions global_init;  // section "global_init"
};

// Adds the mapper's sections to a config schema / reads them from a loaded config
// (InputError naming the file and key for calibration options that fail their Check()).
void AddGlobalMapperSections(ConfigSchema* schema);
void ReadGlobalMapperOptions(const Config& config, GlobalMapperOptions* options);

struct GlobalMapperResult {
  // The cameras the mapper ends with: the tracks' own, with the focals step 2 estimated.
  // Every later stage must use these (TracksWithCameras).
  std::map<uint32_t, Camera> cameras;
  ViewGraphCalibrationResult calibration;  // step 2 (empty when no camera was estimated)
  std::vector<TwoViewGeometry> pairs;
  GlobalInitResult init;  // poses, kept triplets with similarities, dropped images
};

// Runs every stage, recording timings and statistics in `report` (stages "pairs",
// "focal_estimation" when a camera is estimated, "pairs_recalibrated" when a focal changed,
// "triplets", "global_init"). Throws InputError when no reconstruction is possible (no
// verified pair, no triplet, averaging failed) with the reason. `front_end`: the image front
// end's verified geometries of these tracks (`pgba run`), or null (EstimatePairs).
GlobalMapperResult RunGlobalMapper(const Reconstruction& tracks, const GlobalMapperOptions& options, Report* report,
                                   const std::vector<TwoViewGeometry>* front_end = nullptr);

// `tracks` with `cameras` in place of its own (a copy; the same ids are expected).
Reconstruction TracksWithCameras(const Reconstruction& tracks, const std::map<uint32_t, Camera>& cameras);

// True if `cameras` differ from the tracks' own in any parameter.
bool CamerasChanged(const Reconstruction& tracks, const std::map<uint32_t, Camera>& cameras);

// WS/pairs.json, WS/triplets.json (kept triplets with their similarities) and WS/init/
// (COLMAP text model: the mapper's cameras, initial poses, points triangulated with them).
void WriteGlobalMapperWorkspace(const std::string& workspace, const Reconstruction& tracks,
                                const GlobalMapperResult& result);

}  // namespace pgba
