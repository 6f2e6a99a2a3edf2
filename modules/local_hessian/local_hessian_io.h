// WS/local_hessians.json: the local Hessian stage's artefact, so that the global BA can be
// re-run alone (`pgba reconstruct --workspace WS`) without recomputing the local BAs.
//
//   {"format": "pgba_local_hessians", "version": 1, "hessians": [
//     {"triplet_index": I, "images": [3 NAMES], "image_ids": [3 IDS], "status": "ok",
//      "local_poses": [{"q": [w, x, y, z], "t": [3]} x 3], "h": [324, row-major],
//      "observation_weight": X, "depth_scale": X, "prior_mu": X, "num_points": N,
//      "num_observations": N, "rms_px": X, "eigenvalue_ratio": X, "newton_step": [18]}, ...]}
// Entries that are not ok keep only index, images and status. V and D are recomputed from h
// on reading (paper eq. 5), so the file cannot hold an inconsistent decomposition; the prior
// and the reduced gradient are not stored (newton_step = -h^-1 g is; optional on reading).
//
// Reading checks the entries against the workspace's triplets (same count, same images in
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
                                     const std::vector<Triplet>& triplets);

}  // namespace pgba
