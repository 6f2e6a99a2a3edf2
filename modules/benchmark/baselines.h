// The refinement methods `pgba benchmark` compares, each from the same initial poses and the
// same tracks (the production pipeline runs only the first, PointlessMapper step 7):
//   pointless  — RefinePointless (mapper/pose_refinement.h): local Hessians, pointless global
//                BA (eq. 5), re-linearised;
//   averaging  — Aver_BA: the same relative motions and solver, scalar weights instead of the
//                Hessians (IRLS motion averaging, the paper's baseline);
//   pointbased — classical BA over poses and triangulated points (Cauchy pass, filter at
//                point_based.filter_max_error_px, Huber pass; Schur complement);
//   pointbased_split — the same BA over the motions' own tracks (triplet_split_tracks.h):
//                the exact objective that the pointless BA approximates (a diagnostic).
#pragma once

#include <map>
#include <vector>

#include "mapper/pose_refinement.h"

namespace pgba {

enum class RefinementMethod { kPointless, kPointBased, kAveraging, kPointBasedSplit };
// "pointless", "pointbased", "averaging", "pointbased_split" (the benchmark's method and
// model folder names).
const char* RefinementMethodName(RefinementMethod method);
constexpr RefinementMethod kAllRefinementMethods[] = {RefinementMethod::kPointless, RefinementMethod::kPointBased,
                                                      RefinementMethod::kAveraging};

// Refines `initial` by `method`. `hessians` (from PrepareLocalHessians on the same
// initialisation) is required for pointless and averaging, used by pointbased_split (its
// motions' tracks; the triplets' without it) and ignored by pointbased. With
// `record_history`, the poses before the first and after every iteration. Throws InputError
// when the method cannot run (no usable motion, no point).
RefinementResult RefinePoses(RefinementMethod method, const Reconstruction& tracks,
                             const std::map<uint32_t, Pose>& initial, const std::vector<LocalMotion>& triplets,
                             const PreparedHessians* hessians, const RefinementOptions& options,
                             bool record_history = false);

}  // namespace pgba
