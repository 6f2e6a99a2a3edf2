// Track positioning: the camera centres refined on the tracks themselves, the averaged
// rotations held fixed (the last step of translation averaging in global_init.h).
//
// Why. Translation averaging (translation_averaging.h) takes each triplet's baseline ratios
// and directions as they came out of its local BA. Those are coupled to the triplet's own
// rotation errors: on a plane, or with a small baseline, a rotation error delta of a view is
// compensated by a translation error of about delta x depth (the image motion of a rotation
// and of a translation over depth are hard to tell apart). On the synthetic planar video
// (baselines of 0.05 at a depth of 2) that is 4-7% of error in each triplet's baseline
// ratios, which chain into a drifting scale along the strip: 1.5% median centre error after
// 60 frames, and a 2 degree tilt of the Sim(3) that aligns such centres with the truth. The
// averaged rotations, however, average out the triplets' rotation errors; with them held
// fixed, the tracks determine the centres well (the same 60 frames: 0.15% of the extent).
//
// How. GLOMAP's global positioning ("Global Structure-from-Motion Revisited", Pan et al.,
// ECCV 2024) likewise solves for centres and points with the rotations fixed, from a random
// start and with BATA residuals (point-to-camera directions). Here the start is already
// good (translation averaging), so the residual is the reprojection error in pixels, robust
// (Cauchy) against outlier observations: points triangulated with the current poses,
// then Levenberg-Marquardt over centres and points (Ceres, points eliminated first).
// Gauge: the centre of the image with the most observations, and the coordinate of the
// farthest image's centre along its largest offset from it (the scale), are held fixed;
// the result is then centred and scaled as translation averaging leaves it (centroid 0,
// median triplet scale lambda_t = 1).
#pragma once

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pgba/geometry/pose.h"
#include "pgba/optim/loss_function_options.h"
#include "pgba/optim/solver_options.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"
#include "pgba/util/json_fields.h"

namespace pgba {

struct TrackPositioningOptions {
  // false: the centres of translation averaging are kept. Off by default for now: with it,
  // the initial poses are close to the final adjustment's (orbit: sigma 0.76 -> 0.56 px,
  // the pointless BA ends at 0.557), which changes what the benchmark's sigma_init and
  // convergence curves show, and tests/apps/reconstruct_cli_test.cc asserts that the global
  // BA improves the initial sigma by 10% (aerial 24: 0.4935 initial, 0.4930 final with it).
  // Turn on with {"global_init": {"track_positioning": {"enabled": true}}}.
  bool enabled = false;
  // Cauchy loss on the reprojection error, scale 2 px (config key "loss_scale_px").
  LossFunctionOptions loss = {LossType::kCauchy, 2.0};
  // Tracks whose rays meet at less than this (degrees) are not used (depth unobservable).
  double min_track_angle_deg = 0.25;
  // Sparse Schur on the points; at most 50 iterations ("max_iterations"), function tolerance
  // 1e-8, parameter tolerance 1e-10; 1 Ceres thread ("num_threads"; 1 keeps the result
  // bit-identical from run to run, 0 = all hardware threads).
  SolverOptions solver = [] {
    SolverOptions s;
    s.linear_solver_type = ceres::SPARSE_SCHUR;
    s.function_tolerance = 1e-8;
    s.parameter_tolerance = 1e-10;
    return s;
  }();
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
template <class Visit>
void JsonFields(TrackPositioningOptions& o, Visit&& visit) {
  visit("enabled", o.enabled);
  visit("loss_scale_px", o.loss.scale);
  visit("min_track_angle_deg", o.min_track_angle_deg);
  visit("max_iterations", o.solver.max_iterations);
  visit("num_threads", o.solver.num_threads);
}
PGBA_JSON_FROM_FIELDS(TrackPositioningOptions)

struct TrackPositioningSummary {
  bool ran = false;        // false: disabled or nothing to do (no tracks on the posed images)
  std::string message;
  int num_points = 0;
  int num_observations = 0;
  int iterations = 0;
  double initial_rms_px = 0.0;  // reprojection RMS of the used observations before / after
  double final_rms_px = 0.0;
  double seconds = 0.0;
};

// Throws InputError for invalid options.
void ValidateTrackPositioningOptions(const TrackPositioningOptions& options);

// Refines the centres of `poses` (rotations unchanged) on the observations of `tracks`.
// `triplets` (their local poses) give the final scale normalisation. Leaves `poses`
// untouched and returns false (summary->message set) when there is nothing to refine (no
// track seen by two posed images), when the solve fails or when the result is not finite.
bool PositionOnTracks(const Reconstruction& tracks, const std::vector<LocalMotion>& triplets,
                      const TrackPositioningOptions& options, std::map<uint32_t, Pose>* poses,
                      TrackPositioningSummary* summary = nullptr);

}  // namespace pgba
