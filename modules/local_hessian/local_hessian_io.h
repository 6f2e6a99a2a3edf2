// WS/local_hessians.json: the local Hessian stage's artefact, so that the global BA can be
// re-run alone (`pgba reconstruct --workspace WS`) without recomputing the local BAs.
//
//   {"format": "pgba_local_hessians", "version": 1, "hessians": [
//     {"motion_index": I, "images": [N NAMES], "image_ids": [N IDS], "status": "ok",
//      "local_poses": [{"q": [w, x, y, z], "t": [3]} x N], "h": [36 N^2, row-major],
//      "observation_weight": X, "depth_scale": X, "prior_mu": X, "num_points": M,
//      "num_observations": M, "rms_px": X, "eigenvalue_ratio": X, "newton_step": [6N]}, ...]}
// N = 3 for the triplets (h 18x18). "triplet_index" is read as "motion_index" (the key of
// files that hold triplets only).
// Entries that are not ok keep only index, images and status. V and D are recomputed from h
// on reading (paper eq. 5), so the file cannot hold an inconsistent decomposition; the prior
// and the reduced gradient are not stored (newton_step = -h^-1 g is; optional on reading).
//
// Reading checks the entries against the workspace's motions (motions.json; same count, same images in
// the same order, by name and id) and h (finite, symmetric, positive semi-definite up to
// rounding): any mismatch or a NaN is a one-line InputError naming the file and the entry.
#pragma once

#include <filesystem>
#include <vector>

#include "modules/local_hessian/local_hessian.h"

namespace pgba {

std::filesystem::path WorkspaceLocalHessiansPath(const std::filesystem::path& workspace);

void WriteLocalHessians(const std::filesystem::path& path, const Reconstruction& tracks,
                        const LocalHessianResult& result);
LocalHessianResult ReadLocalHessians(const std::filesystem::path& path, const Reconstruction& tracks,
                                     const std::vector<LocalMotion>& motions);

}  // namespace pgba
