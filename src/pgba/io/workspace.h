// Workspace files of the global initialisation and of the relative motions: WS/pairs.json,
// WS/triplets.json and WS/motions.json, so that a run can resume and a later stage can be
// re-run alone.
//
// Layout (JSON, one entry per line so that diffs and greps stay readable):
//   pairs.json:    {"format": "pgba_pairs", "version": 1, "pairs": [
//                    {"image1": NAME, "image2": NAME, "image_id1": ID, "image_id2": ID,
//                     "R_21": [9, row-major], "t_21": [3], "num_tracks": N, "num_inliers": N,
//                     "median_triangulation_angle_deg": X}, ...]}
//   triplets.json: {"format": "pgba_triplets", "version": 1, "triplets": [
//                    {"images": [3 NAMES], "image_ids": [3 IDS],
//                     "local_poses": [{"q": [w, x, y, z], "t": [3]} x 3]   (COLMAP q, t = -R c),
//                     "track_ids": [...], "rms_px": X,
//                     "global_to_local": {"s": X, "R": [9, row-major], "t": [3]}}, ...]}
//   motions.json:  {"format": "pgba_motions", "version": 1, "triplet_rotation_misfit": X,
//                   "linearization_poses": [{"image": NAME, "image_id": ID, "q": [4], "t": [3]}, ...],
//                   "motions": [entries as in triplets.json, N >= 3 views each]}
// Doubles are written with round-trip precision. Images are identified by name (the ids are
// stored for a consistency check): reading against a tracks model whose names or ids do not
// match, a wrong format or version, a malformed value (non-finite number, non-rotation
// matrix, zero translation, repeated image) or a track id absent from the model raises a
// one-line InputError naming the file and the entry. Writes are atomic.
#pragma once

#include <filesystem>
#include <map>
#include <vector>

#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

constexpr int kWorkspaceVersion = 1;

std::filesystem::path WorkspacePairsPath(const std::filesystem::path& workspace);     // WS/pairs.json
std::filesystem::path WorkspaceTripletsPath(const std::filesystem::path& workspace);  // WS/triplets.json
std::filesystem::path WorkspaceMotionsPath(const std::filesystem::path& workspace);   // WS/motions.json

// Every image id must be in `tracks` (its name is written); InputError otherwise.
void WritePairs(const std::filesystem::path& path, const Reconstruction& tracks,
                const std::vector<TwoViewGeometry>& pairs);
std::vector<TwoViewGeometry> ReadPairs(const std::filesystem::path& path, const Reconstruction& tracks);

void WriteTriplets(const std::filesystem::path& path, const Reconstruction& tracks,
                   const std::vector<LocalMotion>& triplets);
std::vector<LocalMotion> ReadTriplets(const std::filesystem::path& path, const Reconstruction& tracks);

// The relative motions whose local Hessians the pointless global BA uses (the PointlessMapper's
// step 5), as chosen and posed by that step, so that a re-run reads them instead of choosing
// them again: each motion's local poses are its linearisation point, and with a far start the
// poses every motion was linearised at (the triplets' pointless BA: the global BA starts
// there too).
struct WorkspaceMotions {
  std::vector<LocalMotion> motions;
  // How far the initial poses were off their triplets' rotations (linearization_start.h).
  double triplet_rotation_misfit = 0.0;
  // Empty: the motions were linearised at the initial poses.
  std::map<uint32_t, Pose> linearization_poses;
};
void WriteMotions(const std::filesystem::path& path, const Reconstruction& tracks, const WorkspaceMotions& motions);
WorkspaceMotions ReadMotions(const std::filesystem::path& path, const Reconstruction& tracks);

}  // namespace pgba
