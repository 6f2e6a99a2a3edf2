// PointlessMapper: the paper's pipeline (section 3.3) from tracks to poses and points, as the
// numbered steps of one Solve():
//   1. view graph: the verified image pairs (the front end's geometries where given)
//   2. focals from the view graph, for the cameras without a prior focal
//   3. triplets: the relative motion of three views from their own BA
//   4. rotation and translation averaging: the initial poses, each triplet's similarity, for
//      every component of the triplet graph (a model each)
//   5. relative motions and their local Hessians (paper eqs. 1-3)
//   6. GCPs: the initial solution moved into their frame (with a GCP file)
//   7. pointless global BA (paper eq. 5), re-linearised at its solution until converged
//   8. every registered image verified against its observations and its verified pairs;
//      a failing one registered again from the structure or dropped (image_verification.h)
//   9. points triangulated with the final poses
//  10. the images left out (no triplet, a weak pair, a component that failed) joined by
//      absolute pose against each model's points, the models merged where they share points
//      (components.h); the models that changed adjusted again (steps 5, 7-9) from their
//      adjusted poses, with the joined images
// Steps 5-9 run for every model; the largest is the result's model (GCPs and the convergence
// curve are its own), the others are more_models.
// `pgba init` runs steps 1-4 (RunGlobalMapper), `pgba reconstruct` and `pgba run` all of them;
// a workspace re-run (ReadMapperWorkspace, mapper_workspace.h) starts with the artefacts of steps 1-5 on disk, and
// Solve runs only the steps whose artefact it does not hold.
#pragma once

#include <string>
#include <vector>

#include "gcp/gcp_alignment.h"
#include "mapper/components.h"
#include "mapper/convergence_curve.h"
#include "mapper/global_mapper.h"
#include "mapper/image_verification.h"
#include "mapper/pose_refinement.h"
#include "pgba/io/json_config.h"
#include "pgba/io/report.h"
#include "pgba/scene/reconstruction.h"

namespace pgba {

struct PointlessMapperOptions {
  GlobalMapperOptions mapper;    // steps 1-4: sections "pairs", "calibration", "triplets", "global_init"
  RefinementOptions refinement;  // steps 5, 7: "local_motions", "local_hessian", "global_ba", "intrinsics"
  // Optional GCP file (io/gcp_file.h; empty: none): step 6 moves the initial solution into the
  // GCP frame and the pointless global BA gets GCP residuals (gcp_residual.h).
  std::string gcp_path;
  GcpOptions gcp;  // section "gcp"
  // The sigma curve over the pointless BA's iterations (paper Figure 3) in the report.
  bool record_convergence = false;  // not a config key (`pgba run` sets it)
  ConvergenceOptions convergence;   // section "convergence"
  ImageVerificationOptions verification;  // step 8: section "verification"
  // Step 10's joining of the images left out and merging of the models. Not a config key.
  ComponentJoiningOptions components;
  // Stop after step 4, the initial solution (`pgba init`). Not a config key.
  bool skip_refinement = false;
  // Where step 5's artefacts (motions.json, local_hessians.json, mapper_workspace.h) are written
  // as soon as the local Hessians are ready, which are then handed to the global BA rather than
  // kept in the result (PreparedHessians::released). Empty: kept, for the caller. Not a config
  // key (`reconstruct` and `run` set their output folder).
  std::string workspace;

  // Empty if valid, else "section.key: problem" for the first invalid option.
  std::string Check() const;
};
void AddPointlessMapperSections(ConfigSchema* schema);
// Reads every section of `config`; InputError naming the file and key for an option that
// fails its Check().
void ReadPointlessMapperOptions(const Config& config, PointlessMapperOptions* options);

// A model beyond the largest: another component of the triplet graph, through steps 5-9.
struct ComponentModel {
  GlobalInitResult init;
  PreparedHessians hessians;
  RefinementResult refined;  // its poses: after the verification
  Reconstruction model;
  ImageVerificationResult verification;
};

// The artefacts of the steps, in step order.
struct PointlessMapperResult {
  GlobalMapperResult initial;  // steps 1-4 (initial.init.success: done), the largest model's
  PreparedHessians hessians;   // step 5 (motions empty: not done)
  RefinementResult refined;    // step 7 (its poses: after step 8's verification)
  ImageVerificationResult verification;  // step 8
  Reconstruction model;        // step 9: the tracks triangulated with the final poses
  ConvergenceCurve convergence;
  // The other models, largest first (models 1, 2, ... of the output).
  std::vector<ComponentModel> more_models;
  // Step 10's images joined by absolute pose and models merged.
  ComponentJoiningResult joining;

  // Every model's final reconstruction, largest first (model, more_models).
  std::vector<const Reconstruction*> Models() const;
  // Every model's step 8, in the order of Models().
  std::vector<const ImageVerificationResult*> Verifications() const;
  // Whether the image has a final pose in a model.
  bool Placed(uint32_t image_id) const;
};

class PointlessMapper {
 public:
  // std::invalid_argument for options that fail Check().
  explicit PointlessMapper(PointlessMapperOptions options);

  // Runs the steps whose artefact `state` does not hold yet (all of them from an empty state),
  // each timed in `report` as a stage ("pairs", "focal_estimation", "pairs_recalibrated",
  // "triplets", "global_init", "local_hessians", "gcp_alignment", "global_ba", "gcp_check",
  // "convergence", "verification", "triangulation", "more_models", "components"; a stage of an
  // adjustment that step 10 runs again is kept as "NAME_before_joining"). Step 10 runs only when
  // steps 1-4 ran here (a workspace's initial poses hold its joined images). `front_end`: the image front end's verified geometries
  // of these tracks (`pgba run`), or null. InputError when no reconstruction is possible,
  // with the reason.
  PointlessMapperResult Solve(const Reconstruction& tracks, Report* report, PointlessMapperResult state = {},
                              const std::vector<TwoViewGeometry>* front_end = nullptr) const;

  const PointlessMapperOptions& options() const { return options_; }

 private:
  PointlessMapperOptions options_;
};

// Steps 1-4 alone (the initial solution), as `pgba init` and `pgba benchmark` run them.
GlobalMapperResult RunGlobalMapper(const Reconstruction& tracks, const GlobalMapperOptions& options, Report* report,
                                   const std::vector<TwoViewGeometry>* front_end = nullptr);

}  // namespace pgba
