// Fuzz target: the workspace's JSON artefacts read against a tracks model: pairs.json,
// triplets.json and motions.json (pgba/io/workspace.h), local_hessians.json (local_hessian/local_hessian_io.h)
// and fingerprint.json (pgba/io/workspace_fingerprint.h). The first byte chooses the file.
#include <Eigen/Geometry>
#include <filesystem>

#include "local_hessian/local_hessian_io.h"
#include "pgba/io/workspace.h"
#include "pgba/io/workspace_fingerprint.h"
#include "pgba/util/input_file.h"
#include "tests/fuzz/fuzz_support.h"

namespace pgba::fuzz {
namespace {

// Four images of one camera, five tracks over them.
const Reconstruction& Tracks() {
  static const Reconstruction rec = [] {
    Reconstruction r;
    Camera cam;
    cam.camera_id = 1;
    cam.model = CameraModel::kPinhole;
    cam.width = 640;
    cam.height = 480;
    cam.params = {500, 500, 320, 240};
    r.cameras[1] = cam;
    for (uint32_t i = 1; i <= 4; ++i) {
      Image im;
      im.image_id = i;
      im.camera_id = 1;
      im.name = "im" + std::to_string(i) + ".jpg";
      r.images[i] = im;
    }
    for (uint64_t p = 1; p <= 5; ++p) {
      Point3D point;
      point.point3D_id = p;
      for (uint32_t i = 1; i <= 4; ++i) {
        Point2D obs;
        obs.xy = Eigen::Vector2d(10.0 * p + i, 20.0 * p - i);
        obs.point3D_id = static_cast<int64_t>(p);
        point.track.push_back({i, static_cast<uint32_t>(r.images[i].points2D.size())});
        r.images[i].points2D.push_back(obs);
      }
      r.points3D[p] = point;
    }
    return r;
  }();
  return rec;
}

std::vector<LocalMotion> Triplets() {
  std::vector<LocalMotion> triplets;
  for (uint32_t first : {1u, 2u}) {
    LocalMotion t;
    t.image_ids = {first, first + 1, first + 2};
    t.local_poses.resize(3);
    for (int k = 0; k < 3; ++k)
      t.local_poses[k] = Pose::FromQt(Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * k, Eigen::Vector3d::UnitY())),
                                      Eigen::Vector3d(-k, 0, 0));
    t.track_ids = {1, 2, 3, 4, 5};
    t.rms_px = 0.5;
    triplets.push_back(t);
  }
  return triplets;
}

std::string Artefact(const char* name, const std::function<void(const std::filesystem::path&)>& write) {
  const std::filesystem::path path = ScratchDir() / name;
  write(path);
  return ReadRegularFile(path.string());
}

}  // namespace

std::vector<std::string> Seeds() {
  const Reconstruction& tracks = Tracks();
  std::vector<TwoViewGeometry> pairs(2);
  pairs[0].image_id1 = 1;
  pairs[0].image_id2 = 2;
  pairs[1].image_id1 = 2;
  pairs[1].image_id2 = 4;
  pairs[1].t_21 = Eigen::Vector3d(0.6, 0, 0.8);
  LocalHessianResult hessians;
  for (const LocalMotion& t : Triplets()) {
    LocalHessian h;
    h.motion_index = static_cast<int>(hessians.hessians.size());
    h.image_ids.assign(t.image_ids.begin(), t.image_ids.end());
    h.status = LocalHessianStatus::kOk;
    h.local_poses.assign(t.local_poses.begin(), t.local_poses.end());
    h.h = SymmetricMatrix(Eigen::MatrixXd::Identity(18, 18));
    h.track_points.resize(t.track_ids.size());
    h.track_points[0].X = Eigen::Vector3d(0.5, -1.0, 4.0);
    h.track_points[0].support = 3;
    hessians.hessians.push_back(h);
  }
  WorkspaceFingerprint f;
  f.tracks = TracksFingerprint(tracks);
  f.init_options = {{"pairs", {{"min_inliers", 30}}}};
  return {"P" + Artefact("seed_pairs.json", [&](const auto& p) { WritePairs(p, tracks, pairs); }),
          "T" + Artefact("seed_triplets.json", [&](const auto& p) { WriteTriplets(p, tracks, Triplets()); }),
          "M" + Artefact("seed_motions.json",
                         [&](const auto& p) { WriteMotions(p, tracks, {Triplets(), 12.5, {{2, Pose()}}}); }),
          "H" + Artefact("seed_hessians.json", [&](const auto& p) { WriteLocalHessians(p, tracks, hessians); }),
          "F" + Artefact("fingerprint.json", [&](const auto& p) { WriteWorkspaceFingerprint(p.parent_path(), f); })};
}

}  // namespace pgba::fuzz

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pgba;
  if (size == 0) return 0;
  const std::string body = fuzz::Bytes(data + 1, size - 1);
  const Reconstruction& tracks = fuzz::Tracks();
  const char kind = static_cast<char>(data[0]);  // the seeds' letters; any other byte: pairs.json
  if (kind == 'T' || kind == 'H') {
    const std::string path = fuzz::WriteScratchFile(kind == 'T' ? "triplets.json" : "local_hessians.json", body);
    fuzz::ExpectValueOrInputError(path, [&] {
      if (kind == 'T') {
        ReadTriplets(path, tracks);
      } else {
        ReadLocalHessians(path, tracks, fuzz::Triplets());
      }
    });
  } else if (kind == 'M') {
    const std::string path = fuzz::WriteScratchFile("motions.json", body);
    fuzz::ExpectValueOrInputError(path, [&] { ReadMotions(path, tracks); });
  } else if (kind == 'F') {
    const std::string path = fuzz::WriteScratchFile("ws/fingerprint.json", body);
    WorkspaceFingerprint expected;
    expected.tracks = TracksFingerprint(tracks);
    expected.init_options = {{"pairs", {{"min_inliers", 30}}}};
    fuzz::ExpectValueOrInputError(path, [&] { CheckWorkspaceFingerprint(fuzz::ScratchDir() / "ws", expected); });
  } else {
    const std::string path = fuzz::WriteScratchFile("pairs.json", body);
    fuzz::ExpectValueOrInputError(path, [&] { ReadPairs(path, tracks); });
  }
  return 0;
}
