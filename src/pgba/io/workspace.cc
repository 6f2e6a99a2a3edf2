#include "pgba/io/workspace.h"

#include "pgba/io/workspace_json.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "pgba/util/atomic_file.h"
#include "pgba/util/error.h"

namespace pgba {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;
using Reader = WorkspaceJsonReader;
using internal_workspace::Array;
using internal_workspace::Document;
using internal_workspace::NameOf;
using internal_workspace::RowMajor;

const char* kPairsFormat = "pgba_pairs";
const char* kTripletsFormat = "pgba_triplets";

}  // namespace

fs::path WorkspacePairsPath(const fs::path& workspace) { return workspace / "pairs.json"; }
fs::path WorkspaceTripletsPath(const fs::path& workspace) { return workspace / "triplets.json"; }
fs::path WorkspaceMotionsPath(const fs::path& workspace) { return workspace / "motions.json"; }

void WritePairs(const fs::path& path, const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs) {
  std::vector<json> entries;
  for (const TwoViewGeometry& p : pairs) {
    entries.push_back({{"image1", NameOf(tracks, p.image_id1, path)},
                       {"image2", NameOf(tracks, p.image_id2, path)},
                       {"image_id1", p.image_id1},
                       {"image_id2", p.image_id2},
                       {"R_21", RowMajor(p.R_21)},
                       {"t_21", Array(p.t_21)},
                       {"num_tracks", p.num_tracks},
                       {"num_inliers", p.num_inliers},
                       {"median_triangulation_angle_deg", p.median_triangulation_angle_deg}});
  }
  WriteStringAtomically(path, Document(kPairsFormat, "pairs", entries));
}

std::vector<TwoViewGeometry> ReadPairs(const fs::path& path, const Reconstruction& tracks) {
  const Reader reader(path, tracks);
  const json entries = reader.Load(kPairsFormat, "pairs");
  std::vector<TwoViewGeometry> pairs;
  for (size_t k = 0; k < entries.size(); ++k) {
    const std::string where = "pairs[" + std::to_string(k) + "]";
    const json& e = entries[k];
    TwoViewGeometry p;
    p.image_id1 = reader.Image(reader.Field(e, "image1", where), reader.Field(e, "image_id1", where), where);
    p.image_id2 = reader.Image(reader.Field(e, "image2", where), reader.Field(e, "image_id2", where), where);
    if (p.image_id1 == p.image_id2) reader.Fail(where, "a pair of an image with itself");
    p.R_21 = reader.Rotation(reader.Field(e, "R_21", where), where + ".R_21");
    p.t_21 = reader.Numbers<3>(reader.Field(e, "t_21", where), where + ".t_21");
    if (!(p.t_21.norm() > 0.0)) reader.Fail(where, "zero translation direction");
    p.num_tracks = static_cast<int>(reader.Integer(reader.Field(e, "num_tracks", where), where));
    p.num_inliers = static_cast<int>(reader.Integer(reader.Field(e, "num_inliers", where), where));
    p.median_triangulation_angle_deg = reader.Number(reader.Field(e, "median_triangulation_angle_deg", where), where);
    pairs.push_back(p);
  }
  return pairs;
}

namespace {

const char* kMotionsFormat = "pgba_motions";

// One motion as a JSON entry (triplets.json, motions.json).
json MotionEntry(const LocalMotion& t, const Reconstruction& tracks, const fs::path& path) {
  json e;
  e["images"] = json::array();
  e["local_poses"] = json::array();
  for (int k = 0; k < t.num_views(); ++k) {
    e["images"].push_back(NameOf(tracks, t.image_ids[k], path));
    e["local_poses"].push_back(internal_workspace::PoseJson(t.local_poses[k]));
  }
  e["image_ids"] = t.image_ids;
  e["track_ids"] = t.track_ids;
  e["rms_px"] = t.rms_px;
  e["global_to_local"] = {
      {"s", t.global_to_local.s}, {"R", RowMajor(t.global_to_local.R)}, {"t", Array(t.global_to_local.t)}};
  return e;
}

// The motion of entry `e`: `views` views (0: any number >= 3), distinct images of the tracks
// model, unit quaternions, track ids of the model, a positive similarity scale.
LocalMotion ReadMotionEntry(const Reader& reader, const Reconstruction& tracks, const json& e, const std::string& where,
                            size_t views) {
  LocalMotion t;
  const json& names = reader.Field(e, "images", where);
  const json& ids = reader.Field(e, "image_ids", where);
  const json& poses = reader.Field(e, "local_poses", where);
  const size_t n = names.is_array() ? names.size() : 0;
  if (!names.is_array() || !ids.is_array() || !poses.is_array() || ids.size() != n || poses.size() != n ||
      (views ? n != views : n < 3))
    reader.Fail(where, "\"images\", \"image_ids\" and \"local_poses\" must hold " +
                           (views ? std::to_string(views) : std::string("the same number (>= 3) of")) + " entries");
  for (size_t v = 0; v < n; ++v) {
    t.image_ids.push_back(reader.Image(names[v], ids[v], where));
    t.local_poses.push_back(reader.PoseOf(poses[v], where + ".local_poses[" + std::to_string(v) + "]"));
  }
  if (!HasDistinctImages(t)) reader.Fail(where, "repeated image");
  const json& track_ids = reader.Field(e, "track_ids", where);
  if (!track_ids.is_array()) reader.Fail(where, "\"track_ids\" must be an array");
  for (const json& id : track_ids) {
    if (!id.is_number_unsigned()) reader.Fail(where, "track id must be a non-negative integer, got " + id.dump());
    t.track_ids.push_back(id.get<uint64_t>());
    if (!tracks.points3D.count(t.track_ids.back()))
      reader.Fail(where, "track id " + id.dump() + " is not in the tracks model");
  }
  t.rms_px = reader.Number(reader.Field(e, "rms_px", where), where + ".rms_px");
  const json& sim = reader.Field(e, "global_to_local", where);
  const std::string sw = where + ".global_to_local";
  t.global_to_local.s = reader.Number(reader.Field(sim, "s", sw), sw + ".s");
  if (!(t.global_to_local.s > 0.0)) reader.Fail(sw, "scale must be positive");
  t.global_to_local.R = reader.Rotation(reader.Field(sim, "R", sw), sw + ".R");
  t.global_to_local.t = reader.Numbers<3>(reader.Field(sim, "t", sw), sw + ".t");
  return t;
}

}  // namespace

void WriteTriplets(const fs::path& path, const Reconstruction& tracks, const std::vector<LocalMotion>& triplets) {
  std::vector<json> entries;
  for (const LocalMotion& t : triplets) {
    if (t.num_views() != 3) ThrowInputError(path.string(), 0, "cannot write a motion of " + std::to_string(t.num_views()) + " views as a triplet");
    entries.push_back(MotionEntry(t, tracks, path));
  }
  WriteStringAtomically(path, Document(kTripletsFormat, "triplets", entries));
}

std::vector<LocalMotion> ReadTriplets(const fs::path& path, const Reconstruction& tracks) {
  const Reader reader(path, tracks);
  const json entries = reader.Load(kTripletsFormat, "triplets");
  std::vector<LocalMotion> triplets;
  for (size_t k = 0; k < entries.size(); ++k)
    triplets.push_back(ReadMotionEntry(reader, tracks, entries[k], "triplets[" + std::to_string(k) + "]", 3));
  return triplets;
}

void WriteMotions(const fs::path& path, const Reconstruction& tracks, const WorkspaceMotions& motions) {
  std::vector<json> entries;
  for (const LocalMotion& m : motions.motions) entries.push_back(MotionEntry(m, tracks, path));
  json start = json::array();
  for (const auto& [id, pose] : motions.linearization_poses) {
    json p = internal_workspace::PoseJson(pose);
    p["image"] = NameOf(tracks, id, path);
    p["image_id"] = id;
    start.push_back(std::move(p));
  }
  const json header = {{"triplet_rotation_misfit", motions.triplet_rotation_misfit}, {"linearization_poses", start}};
  WriteStringAtomically(path, Document(kMotionsFormat, "motions", entries, header));
}

WorkspaceMotions ReadMotions(const fs::path& path, const Reconstruction& tracks) {
  const Reader reader(path, tracks);
  const json doc = reader.LoadDocument(kMotionsFormat, "motions");
  WorkspaceMotions out;
  const json& entries = doc["motions"];
  for (size_t k = 0; k < entries.size(); ++k)
    out.motions.push_back(ReadMotionEntry(reader, tracks, entries[k], "motions[" + std::to_string(k) + "]", 0));
  out.triplet_rotation_misfit = reader.Number(reader.Field(doc, "triplet_rotation_misfit", ""), "triplet_rotation_misfit");
  const json& start = reader.Field(doc, "linearization_poses", "");
  if (!start.is_array()) reader.Fail("linearization_poses", "must be an array");
  for (size_t k = 0; k < start.size(); ++k) {
    const std::string where = "linearization_poses[" + std::to_string(k) + "]";
    const uint32_t id = reader.Image(reader.Field(start[k], "image", where), reader.Field(start[k], "image_id", where), where);
    if (!out.linearization_poses.emplace(id, reader.PoseOf(start[k], where)).second) reader.Fail(where, "repeated image");
  }
  return out;
}

}  // namespace pgba
