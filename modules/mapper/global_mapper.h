// The global mapper: the pipeline from tracks to an initial global solution, reading like
// the paper's steps 2 (relative motions and initial global solution):
//   verified pairs -> triplets (+ triplet BA) -> rotation averaging -> translation
//   averaging -> per-triplet global->local similarities.
// `pgba init` runs it and writes the workspace; `reconstruct` and `benchmark` continue from
// its result in the same process.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "averaging/global_init.h"
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
  TripletOptions triplets;       // section "triplets"
  GlobalInitOptions global_init;  // section "global_init"
};

// Adds the mapper's sections to a config schema / reads them from a loaded config.
void AddGlobalMapperSections(ConfigSchema* schema);
void ReadGlobalMapperOptions(const Config& config, GlobalMapperOptions* options);

struct GlobalMapperResult {
  std::vector<TwoViewGeometry> pairs;
  GlobalInitResult init;  // poses, kept triplets with similarities, dropped images
};

// Runs every stage, recording timings and statistics in `report` (stages "pairs",
// "triplets", "global_init"). Throws InputError when no reconstruction is possible (no
// verified pair, no triplet, averaging failed) with the reason.
GlobalMapperResult RunGlobalMapper(const Reconstruction& tracks, const GlobalMapperOptions& options, Report* report);

// WS/pairs.json, WS/triplets.json (kept triplets with their similarities) and WS/init/
// (COLMAP text model: initial poses, points triangulated with them).
void WriteGlobalMapperWorkspace(const std::string& workspace, const Reconstruction& tracks,
                                const GlobalMapperResult& result);

}  // namespace pgba
