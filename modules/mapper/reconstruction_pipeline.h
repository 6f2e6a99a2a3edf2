// The pipeline of `pgba reconstruct` (and the back half of `pgba run`), from tracks to the
// final poses, reading like the paper's section 3.3:
//   global mapper (relative motions, initial global solution)
//   -> local hessian BA per triplet -> pointless global BA -> points triangulated.
#pragma once

#include <string>

#include "global_ba/gcp_alignment.h"
#include "mapper/convergence_curve.h"
#include "mapper/global_mapper.h"
#include "mapper/pose_refinement.h"
#include "pgba/io/json_config.h"
#include "pgba/io/report.h"
#include "pgba/scene/reconstruction.h"

namespace pgba {

struct ReconstructionOptions {
  GlobalMapperOptions mapper;    // sections "pairs", "triplets", "global_init"
  RefinementOptions refinement;  // sections "local_hessian", "global_ba", "point_based"
  // Optional GCP file (io/gcp_file.h; empty: none): the initial solution is moved into the
  // GCP frame and the pointless global BA gets GCP residuals (gcp_residual.h).
  std::string gcp_path;
  GcpOptions gcp;  // section "gcp"
  // The sigma curve of `pgba run`'s report (Reconstruct with record_convergence).
  ConvergenceOptions convergence;  // section "convergence"
};
void AddReconstructionSections(ConfigSchema* schema);
void ReadReconstructionOptions(const Config& config, ReconstructionOptions* options);

struct ReconstructionOutput {
  GlobalMapperResult init;
  PreparedHessians hessians;
  RefinementResult refined;
  Reconstruction model;  // the tracks triangulated with the refined poses
  // sigma_rms of (a sample of) the tracks before and after every iteration of the pointless
  // global BA (paper Figure 3), if requested.
  ConvergenceCurve convergence;
};

// Every stage, timed in `report` ("pairs", "triplets", "global_init", "local_hessians",
// "global_ba", "triangulation", and "convergence" if requested; with GCPs also
// "gcp_alignment" and "gcp_check", the GCPs triangulated with the final poses vs their given
// coordinates); InputError when no reconstruction is possible. `front_end`: the image front
// end's verified geometries of these tracks, or null (RunGlobalMapper).
ReconstructionOutput Reconstruct(const Reconstruction& tracks, const ReconstructionOptions& options, Report* report,
                                 bool record_convergence = false,
                                 const std::vector<TwoViewGeometry>* front_end = nullptr);

// Continues from the workspace of an earlier `init` or `reconstruct`: WS/pairs.json,
// WS/triplets.json and the initial poses of WS/init/ (matched to `tracks` by image name), and
// WS/local_hessians.json where present (computed otherwise); then as Reconstruct. A missing
// or foreign artefact is an InputError naming the file.
ReconstructionOutput ReconstructFromWorkspace(const Reconstruction& tracks, const std::string& workspace,
                                             const ReconstructionOptions& options, Report* report);

// OUT/pairs.json, OUT/triplets.json, OUT/init/ (the workspace of `init`),
// OUT/local_hessians.json, OUT/sparse/ (COLMAP text model) and OUT/points.ply.
void WriteReconstruction(const std::string& out, const Reconstruction& tracks, const ReconstructionOutput& result);

}  // namespace pgba
