#include "modules/local_hessian/local_hessian_io.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <string>

#include "modules/local_hessian/reduced_camera_matrix.h"
#include "pgba/io/workspace_json.h"
#include "pgba/util/atomic_file.h"

namespace pgba {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;
const char* kFormat = "pgba_local_hessians";

LocalHessianStatus StatusFromName(const WorkspaceJsonReader& reader, const json& j, const std::string& where) {
  if (j.is_string())
    for (int s = 0; s < kNumLocalHessianStatus; ++s)
      if (j.get<std::string>() == LocalHessianStatusName(static_cast<LocalHessianStatus>(s)))
        return static_cast<LocalHessianStatus>(s);
  reader.Fail(where, "unknown status " + j.dump());
}

// LocalHessian::intrinsic_* from [{"camera_id", "free": [indices], "values": [...]}, ...].
void ReadIntrinsicUnknowns(const WorkspaceJsonReader& reader, const Reconstruction& tracks, const json& j,
                           const std::string& where, LocalHessian* lh) {
  if (!j.is_array()) reader.Fail(where, "must be an array");
  std::vector<double> values;
  for (size_t c = 0; c < j.size(); ++c) {
    const std::string w = where + "[" + std::to_string(c) + "]";
    const int64_t id = reader.Integer(reader.Field(j[c], "camera_id", w), w + ".camera_id");
    const auto cam = tracks.cameras.find(static_cast<uint32_t>(id));
    if (id < 0 || cam == tracks.cameras.end()) reader.Fail(w, "camera_id " + std::to_string(id) + " not in the tracks");
    if (!lh->intrinsic_camera_ids.empty() && !(static_cast<uint32_t>(id) > lh->intrinsic_camera_ids.back()))
      reader.Fail(w, "camera ids must ascend");
    const json& free = reader.Field(j[c], "free", w);
    const int np = CameraModelNumParams(cam->second.model);
    if (!free.is_array() || free.empty() || static_cast<int>(free.size()) > np)
      reader.Fail(w, "\"free\" must hold 1 to " + std::to_string(np) + " parameter indices");
    std::vector<int> indices;
    for (const json& f : free) {
      const int64_t i = reader.Integer(f, w + ".free");
      if (i < 0 || i >= np || (!indices.empty() && i <= indices.back()))
        reader.Fail(w, "\"free\" must ascend within 0.." + std::to_string(np - 1));
      indices.push_back(static_cast<int>(i));
    }
    const Eigen::VectorXd v = reader.Numbers(reader.Field(j[c], "values", w), indices.size(), w + ".values");
    values.insert(values.end(), v.data(), v.data() + v.size());
    lh->intrinsic_camera_ids.push_back(static_cast<uint32_t>(id));
    lh->intrinsic_free.push_back(std::move(indices));
  }
  lh->intrinsics0 = Eigen::Map<const Eigen::VectorXd>(values.data(), values.size());
}

// LocalHessian::track_points from [[x, y, z, support] or null per track of the motion].
std::vector<PointStart> ReadPoints(const WorkspaceJsonReader& reader, const json& j, const LocalMotion& motion,
                                   const std::string& where) {
  if (!j.is_array() || j.size() != motion.track_ids.size())
    reader.Fail(where, "must hold one entry per track of the motion (" + std::to_string(motion.track_ids.size()) + ")");
  std::vector<PointStart> points(j.size());
  for (size_t i = 0; i < j.size(); ++i) {
    if (j[i].is_null()) continue;
    const Eigen::Vector4d v = reader.Numbers<4>(j[i], where + "[" + std::to_string(i) + "]");
    if (!(v(3) >= 0) || v(3) != std::floor(v(3)))
      reader.Fail(where + "[" + std::to_string(i) + "]", "support must be a non-negative integer");
    points[i].X = v.head<3>();
    points[i].support = static_cast<int>(v(3));
  }
  return points;
}

}  // namespace

fs::path WorkspaceLocalHessiansPath(const fs::path& workspace) { return workspace / "local_hessians.json"; }

void WriteLocalHessians(const fs::path& path, const Reconstruction& tracks, const LocalHessianResult& result) {
  // One motion's entry at a time: the file is written as it is made.
  const auto entry = [&](size_t k) {
    const LocalHessian& lh = result.hessians[k];
    json e;
    e["motion_index"] = lh.motion_index;
    e["images"] = json::array();
    for (uint32_t id : lh.image_ids) e["images"].push_back(internal_workspace::NameOf(tracks, id, path));
    e["image_ids"] = lh.image_ids;
    e["status"] = LocalHessianStatusName(lh.status);
    if (lh.status == LocalHessianStatus::kOk) {
      e["local_poses"] = json::array();
      for (const Pose& p : lh.local_poses) e["local_poses"].push_back(internal_workspace::PoseJson(p));
      // Self-calibration: the intrinsic unknowns of h after the poses (absent: none).
      for (size_t c = 0, offset = 0; c < lh.intrinsic_camera_ids.size(); ++c) {
        const std::vector<int>& free = lh.intrinsic_free[c];
        e["intrinsics"].push_back({{"camera_id", lh.intrinsic_camera_ids[c]},
                                   {"free", free},
                                   {"values", std::vector<double>(lh.intrinsics0.data() + offset,
                                                                  lh.intrinsics0.data() + offset + free.size())}});
        offset += free.size();
      }
      json h = json::array();
      for (int r = 0; r < lh.h.rows(); ++r)
        for (int c = 0; c < lh.h.cols(); ++c) h.push_back(lh.h(r, c));  // both triangles
      e["h"] = h;
      e["observation_weight"] = lh.observation_weight;
      e["depth_scale"] = lh.depth_scale;
      e["prior_mu"] = lh.prior_mu;
      e["num_points"] = lh.num_points;
      e["num_observations"] = lh.num_observations;
      e["rms_px"] = lh.rms_px;
      e["robust_cost"] = lh.robust_cost;
      e["eigenvalue_ratio"] = lh.eigenvalue_ratio;
      e["newton_step"] = std::vector<double>(lh.newton_step.data(), lh.newton_step.data() + lh.newton_step.size());
      // The points at local_poses, where the next re-linearisation's triangulation starts.
      if (!lh.track_points.empty()) {
        json points = json::array();
        for (const PointStart& p : lh.track_points)
          points.push_back(p.X.allFinite() ? json{p.X.x(), p.X.y(), p.X.z(), p.support} : json());
        e["points"] = std::move(points);
      }
    }
    return e;
  };
  internal_workspace::WriteDocument(path, kFormat, "hessians", result.hessians.size(), entry);
}

LocalHessianResult ReadLocalHessians(const fs::path& path, const Reconstruction& tracks,
                                     const std::vector<LocalMotion>& motions) {
  const WorkspaceJsonReader reader(path, tracks);
  const json entries = reader.Load(kFormat, "hessians");
  if (entries.size() != motions.size())
    reader.Fail("", std::to_string(entries.size()) + " hessians for " + std::to_string(motions.size()) +
                        " motions (workspace of another run? re-run the local hessian stage)");
  LocalHessianResult result;
  for (size_t k = 0; k < entries.size(); ++k) {
    const std::string where = "hessians[" + std::to_string(k) + "]";
    const json& e = entries[k];
    LocalHessian lh;
    const char* index_key = e.contains("motion_index") ? "motion_index" : "triplet_index";
    lh.motion_index = static_cast<int>(reader.Integer(reader.Field(e, index_key, where), where));
    if (lh.motion_index != static_cast<int>(k))
      reader.Fail(where, std::string(index_key) + " must be " + std::to_string(k));
    const json& names = reader.Field(e, "images", where);
    const json& ids = reader.Field(e, "image_ids", where);
    const size_t n = motions[k].image_ids.size();
    if (!names.is_array() || names.size() != n || !ids.is_array() || ids.size() != n)
      reader.Fail(where, "\"images\" and \"image_ids\" must hold " + std::to_string(n) +
                             " entries, the views of motion " + std::to_string(k) + " (another run?)");
    lh.image_ids.resize(n);
    for (size_t v = 0; v < n; ++v) {
      lh.image_ids[v] = reader.Image(names[v], ids[v], where);
      if (lh.image_ids[v] != motions[k].image_ids[v])
        reader.Fail(where, "images differ from motion " + std::to_string(k) + " of the workspace (another run?)");
    }
    lh.status = StatusFromName(reader, reader.Field(e, "status", where), where + ".status");
    if (lh.status == LocalHessianStatus::kOk) {
      if (e.contains("intrinsics")) ReadIntrinsicUnknowns(reader, tracks, e["intrinsics"], where + ".intrinsics", &lh);
      const int dim = 6 * static_cast<int>(n) + lh.num_intrinsics();
      const json& poses = reader.Field(e, "local_poses", where);
      if (!poses.is_array() || poses.size() != n)
        reader.Fail(where, "\"local_poses\" must hold " + std::to_string(n) + " entries");
      lh.local_poses.resize(n);
      for (size_t v = 0; v < n; ++v)
        lh.local_poses[v] = reader.PoseOf(poses[v], where + ".local_poses[" + std::to_string(v) + "]");
      const Eigen::VectorXd h = reader.Numbers(reader.Field(e, "h", where), dim * dim, where + ".h");
      const Eigen::MatrixXd dense =
          Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(h.data(), dim, dim);
      const double scale = dense.cwiseAbs().maxCoeff();
      if (!(scale > 0)) reader.Fail(where + ".h", "zero matrix");
      if ((dense - dense.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) reader.Fail(where + ".h", "not symmetric");
      lh.h = SymmetricMatrix(dense);
      if (Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(dense, Eigen::EigenvaluesOnly).eigenvalues()(0) < -1e-9 * scale)
        reader.Fail(where + ".h", "not positive semi-definite");
      lh.factor = HessianFactor::kEigen;  // paper eq. 5
      lh.observation_weight = reader.Number(reader.Field(e, "observation_weight", where), where);
      lh.depth_scale = reader.Number(reader.Field(e, "depth_scale", where), where);
      if (!(lh.observation_weight > 0) || !(lh.depth_scale > 0))
        reader.Fail(where, "observation_weight and depth_scale must be positive");
      lh.prior_mu = reader.Number(reader.Field(e, "prior_mu", where), where);
      lh.num_points = static_cast<int>(reader.Integer(reader.Field(e, "num_points", where), where));
      lh.num_observations = static_cast<int>(reader.Integer(reader.Field(e, "num_observations", where), where));
      lh.rms_px = reader.Number(reader.Field(e, "rms_px", where), where);
      // Optional (absent: unknown, so the first re-linearised step of a checked
      // re-linearisation is taken unchecked).
      lh.robust_cost = e.contains("robust_cost") ? reader.Number(e["robust_cost"], where + ".robust_cost")
                                                 : std::numeric_limits<double>::quiet_NaN();
      lh.eigenvalue_ratio = reader.Number(reader.Field(e, "eigenvalue_ratio", where), where);
      // Optional (absent: 0, the paper's eq. 5 without gradient).
      lh.newton_step = e.contains("newton_step") ? reader.Numbers(e["newton_step"], dim, where + ".newton_step")
                                                 : Eigen::VectorXd::Zero(dim);
      // Optional (absent: the next re-linearisation triangulates from scratch).
      if (e.contains("points")) lh.track_points = ReadPoints(reader, e["points"], motions[k], where + ".points");
    }
    ++result.status_counts[static_cast<int>(lh.status)];
    result.hessians.push_back(lh);
  }
  return result;
}

}  // namespace pgba
