// The convergence curve of `pgba run`'s report.html (paper Figure 3): sigma_rms of the tracks
// under the poses before and after every iteration of the pointless global BA. It produces
// no pose: it only draws a picture, yet every point re-triangulates the tracks it covers
// (9 s per iteration at 689k tracks: 17-54 s of a 1,000-image run when it covered them all),
// so it covers a deterministic sample of the tracks: `pgba benchmark`'s curves, which compare
// methods, stay exact (modules/benchmark).
#pragma once

#include <cstddef>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pgba/geometry/pose.h"
#include "pgba/scene/reconstruction.h"

namespace pgba {

struct ConvergenceOptions {
  // Tracks the curve is evaluated on: evenly spaced in id order so that at most this many
  // remain (0 = every track, the exact curve). Range >= 0. The default 20,000 bounds a point
  // at ~0.1-0.3 s whatever the size of the block. Measured: on the 150-image rendered aerial
  // block (111,132 tracks) the sampled curve took 0.6-0.8 s against 7.1 s for the exact one
  // (6 iterations, load ~6) and read 0.3145 / 0.1708 px (initial / final) against 0.3127 /
  // 0.1673 px (0.6% / 2.1%); on a synthetic orbit 1,000 tracks were within 0.72%
  // (convergence_curve_test.cc). report.html says it is a sample and gives the exact final
  // sigma beside it.
  int max_tracks = 20000;
  // "" if valid: max_tracks >= 0.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(ConvergenceOptions, max_tracks)

struct ConvergenceCurve {
  std::vector<double> sigma;    // sigma_rms per entry of the history (px; NaN if not computable)
  size_t tracks_evaluated = 0;  // tracks of the sample (all of them when not sampled)
  size_t tracks_total = 0;
  bool Sampled() const { return tracks_evaluated < tracks_total; }
  nlohmann::json ToJson() const;  // {"iterations", "tracks_evaluated", "tracks_total", "sampled"}
};

// The tracks of `tracks` the curve uses: all of them when they are at most max_tracks (or
// max_tracks is 0), otherwise the ones at positions floor(k n / max_tracks) in id order.
// Same cameras and images (every observation keeps its index), only fewer points3D.
Reconstruction ConvergenceSample(const Reconstruction& tracks, const ConvergenceOptions& options);

// sigma_rms (evaluation/sigma.h, default options) of the sample under every pose set of
// `history`. std::invalid_argument for options failing Check(). Deterministic for any
// thread count (EvaluateSigma is).
ConvergenceCurve EvaluateConvergence(const Reconstruction& tracks, const std::vector<std::map<uint32_t, Pose>>& history,
                                     const ConvergenceOptions& options);

}  // namespace pgba
