// Workspace files of the global initialisation: WS/pairs.json and WS/triplets.json, so that
// a run can resume and a later stage can be re-run alone.
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
// Doubles are written with round-trip precision. Images are identified by name (the ids are
// stored for a consistency check): reading against a tracks model whose names or ids do not
// match, a wrong format or version, a malformed value (non-finite number, non-rotation
// matrix, zero translation, repeated image) or a track id absent from the model raises a
// one-line InputError naming the file and the entry. Writes are atomic.
#pragma once

#include <filesystem>
#include <vector>

#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

constexpr int kWorkspaceVersion = 1;

std::filesystem::path WorkspacePairsPath(const std::filesystem::path& workspace);     // WS/pairs.json
std::filesystem::path WorkspaceTripletsPath(const std::filesystem::path& workspace);  // WS/triplets.json

// Every image id must be in `tracks` (its name is written); InputError otherwise.
void WritePairs(const std::filesystem::path& path, const Reconstruction& tracks,
                const std::vector<TwoViewGeometry>& pairs);
std::vector<TwoViewGeometry> ReadPairs(const std::filesystem::path& path, const Reconstruction& tracks);

void WriteTriplets(const std::filesystem::path& path, const Reconstruction& tracks,
                   const std::vector<Triplet>& triplets);
std::vector<Triplet> ReadTriplets(const std::filesystem::path& path, const Reconstruction& tracks);

}  // namespace pgba
