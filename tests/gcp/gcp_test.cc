// Ground control points (paper, "Inclusion of ground control points"): the GCP residual
// against an independent inverse similarity, the frame transfer, the pointless global BA
// pulled by a deliberately shifted GCP exactly as a rigid block would be, and the whole
// `reconstruct` pipeline ending in the GCP frame without any alignment to the truth.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <filesystem>

#include "mapper/pointless_mapper.h"
#include "modules/gcp/gcp_alignment.h"
#include "modules/global_ba/gcp_residual.h"
#include "modules/global_ba/global_ba.h"
#include "pgba/io/gcp_file.h"
#include "pgba/util/error.h"
#include "tests/global_ba/global_ba_fixture.h"

namespace pgba {
namespace {

using namespace pgba::testing;
namespace fs = std::filesystem;

// The GCP frame: a known similarity of the truth, far from it (a map projection's offsets).
Sim3 GcpFrame() {
  Sim3 S;
  S.s = 2.5;
  S.R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  S.t = Eigen::Vector3d(1000.0, -2000.0, 300.0);
  return S;
}

std::map<uint32_t, Pose> Transformed(const Sim3& S, const std::map<uint32_t, Pose>& poses) {
  std::map<uint32_t, Pose> out;
  for (const auto& [id, p] : poses) out[id] = S.Apply(p);
  return out;
}

// `count` true points of `rec` seen in >= 3 images, spread over the point ids, in the frame S,
// observed at their (noisy) track pixels.
std::vector<GcpFileEntry> MakeGcps(const Reconstruction& rec, const Sim3& S, int count, double sigma) {
  std::vector<const Point3D*> candidates;
  for (const auto& [id, pt] : rec.points3D)
    if (pt.track.size() >= 3) candidates.push_back(&pt);
  std::vector<GcpFileEntry> gcps;
  if (candidates.size() < static_cast<size_t>(count)) return gcps;  // the callers check the count
  for (int i = 0; i < count; ++i) {
    const Point3D& pt = *candidates[i * candidates.size() / count];
    GcpFileEntry g;
    g.name = "gcp" + std::to_string(i);
    g.X = S.Apply(pt.xyz);
    g.sigma = sigma;
    for (const TrackElement& el : pt.track) {
      const Image& im = rec.images.at(el.image_id);
      g.observations.push_back({im.name, im.points2D[el.point2D_idx].xy, 0});
    }
    gcps.push_back(g);
  }
  return gcps;
}

struct CentreErrors {
  double median = 0.0, max = 0.0;
};
// |C_est - C_ref| over the images of `est`, as fractions of `extent`; no alignment.
CentreErrors RawCentreErrors(const std::map<uint32_t, Pose>& est, const std::map<uint32_t, Pose>& ref, double extent) {
  std::vector<double> e;
  for (const auto& [id, p] : est) e.push_back((p.C() - ref.at(id).C()).norm() / extent);
  std::sort(e.begin(), e.end());
  return {e[e.size() / 2], e.back()};
}

TEST(GcpResidual, IsTheWhitenedGapToTheInverseSimilarity) {
  MotionSimilarity sim;
  sim.alpha0 = Eigen::AngleAxisd(0.4, Eigen::Vector3d(0.3, -1, 0.2).normalized()).toRotationMatrix();
  sim.G = Eigen::Vector3d(5, -3, 2);
  sim.x << 0.5, -0.2, 1.5, 0.01, -0.02, 0.03, 1.7;  // beta, theta, lambda
  const Sim3 d = sim.ToSim3();  // global -> local, independent of the residual's algebra
  GcpTripletTerm t;
  t.P = Eigen::Vector3d(7, 1, -4);
  const Eigen::Vector3d delta(0.03, -0.01, 0.02);  // error of the local triangulation
  t.p_local = d.Apply(t.P) + delta;
  t.sigma = 0.05;
  const GcpResidual f(t, sim);
  double r[3];
  ASSERT_TRUE(f(sim.x.data(), r));
  const Eigen::Vector3d expected = (t.P - d.Inverse().Apply(t.p_local)) / t.sigma;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r[i], expected(i), 1e-12);
  // The gap is the local error mapped back to the global frame: -R^T delta / s.
  EXPECT_NEAR((Eigen::Map<Eigen::Vector3d>(r) + d.R.transpose() * delta / d.s / t.sigma).norm(), 0.0, 1e-12);
  // At the exact triangulation the residual vanishes.
  t.p_local = d.Apply(t.P);
  ASSERT_TRUE(GcpResidual(t, sim)(sim.x.data(), r));
  EXPECT_NEAR(Eigen::Map<Eigen::Vector3d>(r).norm(), 0.0, 1e-12);
}

TEST(GcpAlignment, MovesPosesAndTripletsIntoTheGcpFrame) {
  RingSceneOptions o;
  o.num_images = 12;
  o.num_points = 600;
  o.noise_px = 0.0;
  const Reconstruction rec = MakeRingScene(o);
  const std::map<uint32_t, Pose> gt = PosesOf(rec);
  // Initial solution in an arbitrary frame A of the truth.
  Sim3 A;
  A.s = 0.3;
  A.R = Eigen::AngleAxisd(-1.1, Eigen::Vector3d(0, 1, 1).normalized()).toRotationMatrix();
  A.t = Eigen::Vector3d(4, 5, -6);
  std::map<uint32_t, Pose> poses = Transformed(A, gt);
  LocalMotion tri;
  tri.image_ids = {1, 2, 3};
  tri.global_to_local.s = 1.9;
  tri.global_to_local.t = Eigen::Vector3d(1, 2, 3);
  std::vector<LocalMotion> triplets = {tri};
  const std::map<uint32_t, Pose> before = poses;

  const Sim3 S = GcpFrame();
  GcpInput in;
  in.gcps = MakeGcpConstraints(MakeGcps(rec, S, 5, 0.01), rec, in.options, "test");
  ASSERT_EQ(in.gcps.size(), 5u);
  const GcpAlignment a = AlignToGcps(in, &poses, &triplets);
  EXPECT_EQ(a.num_gcps_used, 5);
  EXPECT_LT(a.rms_before, 1e-6);
  const double extent = SceneExtent(Transformed(S, gt));
  const CentreErrors e = RawCentreErrors(poses, Transformed(S, gt), extent);
  EXPECT_LT(e.max, 1e-8);
  for (const auto& [id, p] : poses)
    EXPECT_LT(RotationAngleDeg(p.R(), gt.at(id).R() * S.R.transpose()), 1e-6) << id;
  // The triplet's local frame is unchanged: d' maps the moved centres where d mapped the old.
  for (uint32_t id : tri.image_ids)
    EXPECT_LT((triplets[0].global_to_local.Apply(poses.at(id).C()) - tri.global_to_local.Apply(before.at(id).C())).norm(),
              1e-9);
  EXPECT_NEAR(CheckGcps(in, poses).rms, 0.0, 1e-6);

  // Fewer than 3 GCPs: no frame.
  in.gcps.resize(2);
  EXPECT_THROW(AlignToGcps(in, &poses, &triplets), InputError);
}

// A GCP 1000 m off (a mistyped coordinate) dragged the whole solution (check rms of hundreds
// of metres, no word): it is dropped, named, and the transfer fits the others exactly.
TEST(GcpAlignment, DropsAnOutlyingGcpAndNamesTheFile) {
  RingSceneOptions o;
  o.num_images = 12;
  o.num_points = 600;
  o.noise_px = 0.0;
  const Reconstruction rec = MakeRingScene(o);
  const std::map<uint32_t, Pose> gt = PosesOf(rec);
  std::map<uint32_t, Pose> poses = gt;
  std::vector<LocalMotion> triplets;
  const Sim3 S = GcpFrame();
  std::vector<GcpFileEntry> entries = MakeGcps(rec, S, 5, 0.05);
  ASSERT_EQ(entries.size(), 5u);
  entries[2].X += Eigen::Vector3d(1000.0, 0.0, 0.0);
  GcpInput in;
  in.path = "site/gcps.txt";
  in.gcps = MakeGcpConstraints(entries, rec, in.options, in.path);
  const GcpAlignment a = AlignToGcps(in, &poses, &triplets);
  EXPECT_EQ(a.dropped, std::vector<std::string>{"gcp2"});
  EXPECT_EQ(a.num_gcps_used, 4);
  EXPECT_LT(a.rms_before, 1e-6);
  ASSERT_EQ(in.gcps.size(), 4u);  // the global BA does not see it
  for (const GcpConstraint& g : in.gcps) EXPECT_NE(g.name, "gcp2");
  const GcpCheck check = CheckGcps(in, poses);
  EXPECT_LT(check.rms, 1e-6);
  EXPECT_TRUE(check.beyond_sigma.empty());
  EXPECT_EQ(check.ToJson()["beyond_sigma"].size(), 0u);
  // Without the transfer's chance to drop it (3 GCPs only), the check names it.
  GcpInput three = in;
  three.gcps.resize(3);
  three.gcps[0].X += Eigen::Vector3d(0.0, 50.0, 0.0);
  EXPECT_EQ(CheckGcps(three, poses).beyond_sigma, std::vector<std::string>{three.gcps[0].name});
  // Too few GCPs: the error names the file.
  in.gcps.resize(2);
  try {
    AlignToGcps(in, &poses, &triplets);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("site/gcps.txt: 2 GCPs triangulated", 0), 0u) << e.what();
  }
}

TEST(GcpConstraints, UnknownImagesAreSkippedAndUnderObservedGcpsDropped) {
  RingSceneOptions o;
  o.num_images = 8;
  o.num_points = 200;
  const Reconstruction rec = MakeRingScene(o);
  std::vector<GcpFileEntry> e(2);
  e[0].name = "a";
  e[0].observations = {{"img1.jpg", {1, 2}, 3}, {"nope.jpg", {1, 2}, 4}, {"img2.jpg", {3, 4}, 5}};
  e[1].name = "b";
  e[1].sigma = 0.5;
  e[1].observations = {{"img1.jpg", {1, 2}, 7}, {"missing.jpg", {1, 2}, 8}};
  GcpOptions options;
  options.default_sigma = 0.2;
  const std::vector<GcpConstraint> g = MakeGcpConstraints(e, rec, options, "f.txt");
  ASSERT_EQ(g.size(), 1u);  // b is left with one observation
  EXPECT_EQ(g[0].name, "a");
  EXPECT_DOUBLE_EQ(g[0].sigma, 0.2);
  ASSERT_EQ(g[0].observations.size(), 2u);
  EXPECT_EQ(g[0].observations[1].image_id, *rec.FindImageByName("img2.jpg"));
}

// The pointless global BA from perturbed poses already transferred to the GCP frame.
struct GcpScenario {
  Reconstruction rec;
  Sim3 S = GcpFrame();
  std::map<uint32_t, Pose> gt_gcp;  // truth in the GCP frame
  std::map<uint32_t, Pose> initial;
  TripletsWithHessians th;
  double extent = 0.0;
};

GcpScenario MakeGcpScenario() {
  GcpScenario s;
  RingSceneOptions o;
  o.num_images = 16;
  o.num_points = 1200;
  o.noise_px = 0.5;
  o.seed = 11;
  s.rec = MakeRingScene(o);
  s.gt_gcp = Transformed(s.S, PosesOf(s.rec));
  s.extent = SceneExtent(s.gt_gcp);
  s.initial = PerturbPoses(s.gt_gcp, 1.0, 0.02 * s.extent, 12);
  s.th = BuildTripletsWithHessians(s.rec, 4, true, 13);
  return s;
}

TEST(GcpGlobalBA, ShiftedGcpPullsTheBlockLikeARigidBody) {
  const GcpScenario s = MakeGcpScenario();
  const GlobalBAOptions options = PaperTripletGlobalBAOptions();
  GcpInput in;
  const double sigma = 0.02 * s.extent;
  std::vector<GcpFileEntry> entries = MakeGcps(s.rec, s.S, 6, sigma);
  ASSERT_EQ(entries.size(), 6u);
  // GCP 0 keeps its whole track (seen by many triplets), the others 3 views (few triplets):
  // only the 1/n weighting makes every GCP count once in where the block goes.
  for (size_t i = 1; i < entries.size(); ++i) entries[i].observations.resize(3);
  in.gcps = MakeGcpConstraints(entries, s.rec, in.options, "test");
  ASSERT_EQ(in.gcps.size(), 6u);

  // Without GCPs the gauge holds a pose of the perturbed start: not the GCP frame.
  const GlobalBAResult free = PointlessGlobalBA(s.initial, s.th.triplets, s.th.hessians.hessians, options);
  // With the true GCPs: the GCP frame, no alignment.
  const GlobalBAResult a = PointlessGlobalBA(s.initial, s.th.triplets, s.th.hessians.hessians, options, nullptr, &in);
  EXPECT_TRUE(a.summary.gcp_gauge);
  EXPECT_GE(a.summary.num_gcp_residuals, 6);
  const CentreErrors e_free = RawCentreErrors(free.poses, s.gt_gcp, s.extent);
  const CentreErrors e_a = RawCentreErrors(a.poses, s.gt_gcp, s.extent);
  // The best any frame could do: the errors after the similarity that fits the truth.
  const PoseErrors aligned = GroundTruthErrors(a.poses, s.gt_gcp);
  std::printf("centre error vs truth in GCP frame / extent: without GCPs median %.2e, with GCPs median %.2e max %.2e "
              "(after a best-fit similarity: median %.2e)\n",
              e_free.median, e_a.median, e_a.max, aligned.center_rel_median);
  EXPECT_GT(e_free.median, 3e-3);
  EXPECT_LT(e_a.median, 3e-3);
  EXPECT_LT(e_a.max, 5e-3);

  // Shift GCP 0 by 5% of the extent. The triplet terms are invariant under a global
  // similarity and far stiffer than the GCPs, so the block moves rigidly, by the
  // similarity U that best maps the GCPs (as the block places them, with equal weights:
  // the 1/n weighting) onto the shifted coordinates.
  GcpInput shifted = in;
  const Eigen::Vector3d d = 0.05 * s.extent * Eigen::Vector3d(0.6, -0.8, 0.0);
  shifted.gcps[0].X += d;
  const GlobalBAResult b =
      PointlessGlobalBA(s.initial, s.th.triplets, s.th.hessians.hessians, options, nullptr, &shifted);
  std::vector<Eigen::Vector3d> placed, target;
  for (const GcpConstraint& g : shifted.gcps) {
    placed.push_back(*TriangulateGcp(g, a.poses, in.options));
    target.push_back(g.X);
  }
  Sim3 U;
  ASSERT_TRUE(EstimateSim3(placed, target, &U));
  const std::map<uint32_t, Pose> expected = Transformed(U, a.poses);
  const CentreErrors moved = RawCentreErrors(b.poses, a.poses, s.extent);
  const CentreErrors off = RawCentreErrors(b.poses, expected, s.extent);
  std::printf("shift of one GCP by %.3f extent: centres moved by median %.2e, off the rigid prediction by %.2e\n",
              d.norm() / s.extent, moved.median, off.median);
  EXPECT_GT(moved.median, 2e-3);         // the shift pulls the block ...
  EXPECT_LT(off.median, 0.1 * moved.median);  // ... by the predicted similarity
  EXPECT_LT(off.max, 0.2 * moved.max);
}

TEST(GcpReconstruct, ResultIsInTheGcpFrameWithoutAlignment) {
  RingSceneOptions o;
  o.num_images = 16;
  o.num_points = 1500;
  o.noise_px = 0.5;
  o.seed = 21;
  const Reconstruction truth = MakeRingScene(o);
  Reconstruction tracks = truth;
  for (auto& [id, im] : tracks.images) im.pose = Pose();
  const Sim3 S = GcpFrame();
  const std::map<uint32_t, Pose> gt_gcp = Transformed(S, PosesOf(truth));
  const double extent = SceneExtent(gt_gcp);

  const fs::path dir = fs::temp_directory_path() / ("pgba_gcp_reconstruct_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::vector<GcpFileEntry> gcps = MakeGcps(truth, S, 10, 0.01);
  gcps[0].observations.push_back({"not_in_tracks.jpg", {10, 10}, 0});  // warned and skipped
  WriteGcpFile(gcps, (dir / "gcp.txt").string());
  PointlessMapperOptions options;
  options.gcp_path = (dir / "gcp.txt").string();
  Report report;
  const PointlessMapperResult out = PointlessMapper(options).Solve(tracks, &report);
  fs::remove_all(dir);

  ASSERT_EQ(out.refined.poses.size(), truth.images.size());
  const CentreErrors e = RawCentreErrors(out.refined.poses, gt_gcp, extent);
  std::vector<double> rot;
  for (const auto& [id, p] : out.refined.poses) rot.push_back(RotationAngleDeg(p.R(), gt_gcp.at(id).R()));
  std::sort(rot.begin(), rot.end());
  const nlohmann::json& stages = report.json().at("stages");
  ASSERT_TRUE(stages.contains("gcp_check") && stages.contains("gcp_alignment"));
  const PoseErrors aligned = GroundTruthErrors(out.refined.poses, gt_gcp);
  std::printf("reconstruct with GCPs: centre error / extent median %.2e max %.2e, rotation median %.4f deg (after a "
              "best-fit similarity: %.2e, %.4f deg), GCP check RMS %.4f m (extent %.1f m)\n",
              e.median, e.max, rot[rot.size() / 2], aligned.center_rel_median, aligned.rot_deg_median,
              stages["gcp_check"]["rms_m"].get<double>(), extent);
  // Raw errors = the solution's own (after a best-fit similarity) + the error of the GCP
  // frame, which comes from 10 GCPs measured at 0.5 px: a few centimetres on 40 m.
  // Without the GCPs the frame would be the mapper's arbitrary one (errors ~ the extent).
  EXPECT_LT(e.median, 2.0 * aligned.center_rel_median + 1e-3);
  EXPECT_LT(e.max, 1e-2);
  EXPECT_LT(rot[rot.size() / 2], aligned.rot_deg_median + 0.15);
  EXPECT_EQ(stages["gcp_alignment"]["gcps"].get<int>(), 10);
  EXPECT_LT(stages["gcp_check"]["rms_m"].get<double>(), 1e-3 * extent);
  EXPECT_GT(stages["global_ba"]["gcp_residuals"].get<int>(), 10);
}

}  // namespace
}  // namespace pgba
