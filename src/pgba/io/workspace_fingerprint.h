// WS/fingerprint.json: what a workspace was computed from, so that `reconstruct
// --workspace WS` refuses the workspace of another scene or of other options instead of
// finishing with a wrong model (another scene with the same image names would go through
// with exit 0, 4 of 70 images and 22 degrees of rotation error).
//
//   {"format": "pgba_fingerprint", "version": 1, "tracks": "<16 hex digits>",
//    "init_options": {"pairs": ..., "triplets": ..., "global_init": ...},
//    "hessian_options": {"local_motions": ..., "local_hessian": ...}}   (when WS holds
//                                                                         local_hessians.json)
// "tracks" hashes the tracks model's content (cameras, image ids, names and cameras,
// observations, tracks; not the poses, which the pipeline ignores). Thread counts are
// left out of the options: results do not depend on them.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "pgba/scene/reconstruction.h"

namespace pgba {

std::filesystem::path WorkspaceFingerprintPath(const std::filesystem::path& workspace);

// 16 hex digits of the tracks model's content (deterministic, address-independent).
std::string TracksFingerprint(const Reconstruction& tracks);

struct WorkspaceFingerprint {
  std::string tracks;
  nlohmann::json init_options = nlohmann::json::object();
  nlohmann::json hessian_options;  // null: the workspace has no local hessians
};

// Options JSON without its thread counts ("num_threads" keys, at any depth).
nlohmann::json WithoutThreadCounts(nlohmann::json options);

void WriteWorkspaceFingerprint(const std::filesystem::path& workspace, const WorkspaceFingerprint& fingerprint);

// InputError naming WS/fingerprint.json when it is missing or malformed, or when the tracks
// or the options that produced the workspace's artefacts differ from `expected` (the first
// differing option is named). The hessian options are compared only when both sides have
// them (a workspace of `init` holds no local hessians: they are computed anew).
void CheckWorkspaceFingerprint(const std::filesystem::path& workspace, const WorkspaceFingerprint& expected);

}  // namespace pgba
