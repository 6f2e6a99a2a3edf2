#include "pgba/io/workspace.h"

#include "pgba/io/workspace_json.h"

#include <algorithm>
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

void WriteTriplets(const fs::path& path, const Reconstruction& tracks, const std::vector<Triplet>& triplets) {
  std::vector<json> entries;
  for (const Triplet& t : triplets) {
    json e;
    e["images"] = json::array();
    e["local_poses"] = json::array();
    for (int k = 0; k < 3; ++k) {
      e["images"].push_back(NameOf(tracks, t.image_ids[k], path));
      const Eigen::Quaterniond& q = t.local_poses[k].q();
      e["local_poses"].push_back({{"q", {q.w(), q.x(), q.y(), q.z()}}, {"t", Array(t.local_poses[k].t())}});
    }
    e["image_ids"] = t.image_ids;
    e["track_ids"] = t.track_ids;
    e["rms_px"] = t.rms_px;
    e["global_to_local"] = {
        {"s", t.global_to_local.s}, {"R", RowMajor(t.global_to_local.R)}, {"t", Array(t.global_to_local.t)}};
    entries.push_back(std::move(e));
  }
  WriteStringAtomically(path, Document(kTripletsFormat, "triplets", entries));
}

std::vector<Triplet> ReadTriplets(const fs::path& path, const Reconstruction& tracks) {
  const Reader reader(path, tracks);
  const json entries = reader.Load(kTripletsFormat, "triplets");
  std::vector<Triplet> triplets;
  for (size_t k = 0; k < entries.size(); ++k) {
    const std::string where = "triplets[" + std::to_string(k) + "]";
    const json& e = entries[k];
    Triplet t;
    const json& names = reader.Field(e, "images", where);
    const json& ids = reader.Field(e, "image_ids", where);
    const json& poses = reader.Field(e, "local_poses", where);
    if (!names.is_array() || names.size() != 3 || !ids.is_array() || ids.size() != 3 || !poses.is_array() ||
        poses.size() != 3)
      reader.Fail(where, "\"images\", \"image_ids\" and \"local_poses\" must hold three entries");
    for (int v = 0; v < 3; ++v) {
      t.image_ids[v] = reader.Image(names[v], ids[v], where);
      const std::string pw = where + ".local_poses[" + std::to_string(v) + "]";
      const Eigen::Vector4d q = reader.Numbers<4>(reader.Field(poses[v], "q", pw), pw + ".q");
      if (!(q.norm() > 0.5 && q.norm() < 2.0)) reader.Fail(pw, "quaternion is not unit");
      t.local_poses[v] = Pose::FromQt(Eigen::Quaterniond(q(0), q(1), q(2), q(3)),
                                      reader.Numbers<3>(reader.Field(poses[v], "t", pw), pw + ".t"));
    }
    if (t.image_ids[0] == t.image_ids[1] || t.image_ids[0] == t.image_ids[2] || t.image_ids[1] == t.image_ids[2])
      reader.Fail(where, "repeated image");
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
    triplets.push_back(std::move(t));
  }
  return triplets;
}

}  // namespace pgba
