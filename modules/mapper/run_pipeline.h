// `pgba run`: the whole mission, from a folder of calibrated photos to poses and points.
//   features (SIFT, cached per image) -> matching + verification -> tracks
//   -> global mapper (its view graph from the verified geometries) -> local hessian BA per triplet -> pointless global BA -> points.
// The output folder is also the workspace: a re-run reuses the cached features and, when
// the matching options and the feature set are unchanged, the tracks.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "features/extract_features.h"
#include "mapper/pointless_mapper.h"
#include "matching/match_images.h"
#include "pgba/io/report.h"

namespace pgba {

struct RunOptions {
  FeatureExtractionOptions features;   // section "features"
  MatchingOptions matching;            // section "matching"
  PointlessMapperOptions reconstruction;  // the sections of `reconstruct`
  // `pgba run --calib-prior` (not a config key): the calibration file is only a prior (a
  // spec-sheet focal, an old calibration), so intrinsics.cameras "auto" refines it in every
  // BA as it does EXIF priors. Default false: a given calibration is held.
  bool calibration_is_prior = false;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
// Loads `path` (empty: defaults) against the schema of every section above. Every command
// reads its config through this, so one preset of configs/ serves run, reconstruct and
// benchmark (sections of stages a command does not run are checked, then unused).
RunOptions LoadRunOptions(const std::string& path);

struct RunOutput {
  Reconstruction tracks;
  PointlessMapperResult reconstruction;  // with its convergence curve
};

// Every stage, timed in `report`; writes OUT/features/, OUT/tracks/, OUT/matching/ on the
// way and the reconstruction's outputs (WriteReconstruction) at the end. InputError when no
// reconstruction is possible, with the reason.
RunOutput RunPipeline(const std::string& images_dir, const CalibrationInput& calibration, const std::string& out,
                      const RunOptions& options, Report* report);

}  // namespace pgba
