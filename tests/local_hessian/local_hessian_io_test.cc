// WS/local_hessians.json: a round trip keeps every Hessian (and the decomposition rebuilt
// from it); a file of another run, a NaN, a broken matrix or a wrong version are one-line
// errors naming the file and the entry.
#include "modules/local_hessian/local_hessian_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "modules/local_hessian/local_motions.h"
#include "pgba/util/error.h"
#include "tests/local_hessian/ring_scene.h"

namespace pgba {
namespace {

namespace fs = std::filesystem;
using namespace pgba::testing;

struct Fixture {
  Reconstruction rec;
  std::vector<LocalMotion> triplets;
  LocalHessianResult result;
};

Fixture Make() {
  RingSceneOptions o;
  o.num_images = 12;
  o.num_points = 1500;
  o.seed = 5;
  Fixture f;
  f.rec = MakeRingScene(o);
  std::mt19937_64 rng(6);
  f.triplets = MakeRingTriplets(f.rec, 3, false, rng);
  f.result = ComputeLocalHessians(f.rec, f.triplets, PaperTripletLocalHessianOptions());
  f.result.hessians[1].status = LocalHessianStatus::kIllConditioned;  // a rejected entry too
  --f.result.status_counts[static_cast<int>(LocalHessianStatus::kOk)];
  ++f.result.status_counts[static_cast<int>(LocalHessianStatus::kIllConditioned)];
  return f;
}

std::string ReadAll(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string ErrorOf(const fs::path& p, const Fixture& f, const std::vector<LocalMotion>& triplets) {
  try {
    ReadLocalHessians(p, f.rec, triplets);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(LocalHessianIo, RoundTripKeepsHessiansAndRebuildsTheDecomposition) {
  const Fixture f = Make();
  ASSERT_GE(f.result.num_ok(), 4);
  const fs::path p = fs::temp_directory_path() / "pgba_lh_roundtrip.json";
  WriteLocalHessians(p, f.rec, f.result);
  const LocalHessianResult back = ReadLocalHessians(p, f.rec, f.triplets);
  ASSERT_EQ(back.hessians.size(), f.result.hessians.size());
  EXPECT_EQ(back.status_counts, f.result.status_counts);
  for (size_t i = 0; i < back.hessians.size(); ++i) {
    const LocalHessian &a = f.result.hessians[i], &b = back.hessians[i];
    EXPECT_EQ(a.status, b.status);
    EXPECT_EQ(a.image_ids, b.image_ids);
    if (a.status != LocalHessianStatus::kOk) continue;
    EXPECT_EQ((a.h.Dense() - b.h.Dense()).cwiseAbs().maxCoeff(), 0.0) << i;
    // W^T W = h whatever eigenvector signs the decomposition picked.
    Eigen::MatrixXd V;
    Eigen::VectorXd D;
    b.Factor(&V, &D);
    const Matrix18d W = D.asDiagonal() * V;
    EXPECT_LT((W.transpose() * W - a.h.Dense()).norm(), 1e-9 * a.h.Dense().norm()) << i;
    EXPECT_EQ(a.observation_weight, b.observation_weight);
    EXPECT_EQ(a.depth_scale, b.depth_scale);
    EXPECT_EQ(a.newton_step, b.newton_step) << i;
    for (int k = 0; k < 3; ++k) EXPECT_LT((a.local_poses[k].C() - b.local_poses[k].C()).norm(), 1e-12);
    // The points the next re-linearisation starts from, bit for bit (NaN: no point).
    ASSERT_EQ(a.track_points.size(), f.triplets[i].track_ids.size());
    ASSERT_EQ(b.track_points.size(), a.track_points.size());
    int points = 0;
    for (size_t t = 0; t < a.track_points.size(); ++t) {
      EXPECT_EQ(a.track_points[t].support, b.track_points[t].support);
      if (!a.track_points[t].X.allFinite()) {
        EXPECT_FALSE(b.track_points[t].X.allFinite());
        continue;
      }
      EXPECT_EQ(a.track_points[t].X, b.track_points[t].X);
      ++points;
    }
    EXPECT_EQ(points, a.num_points) << i;
  }
  fs::remove(p);
}

TEST(LocalHessianIo, ForeignOrDamagedFilesAreErrorsNamingTheEntry) {
  const Fixture f = Make();
  const fs::path p = fs::temp_directory_path() / "pgba_lh_damaged.json";
  WriteLocalHessians(p, f.rec, f.result);
  const std::string good = ReadAll(p);

  // Another run: fewer triplets, or the triplets in another order.
  std::vector<LocalMotion> fewer(f.triplets.begin(), f.triplets.end() - 1);
  EXPECT_NE(ErrorOf(p, f, fewer).find("hessians for"), std::string::npos);
  std::vector<LocalMotion> swapped = f.triplets;
  std::swap(swapped[0], swapped[2]);
  const std::string e_swap = ErrorOf(p, f, swapped);
  EXPECT_NE(e_swap.find("hessians[0]"), std::string::npos) << e_swap;
  EXPECT_NE(e_swap.find(p.string()), std::string::npos) << e_swap;

  auto with = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    std::ofstream(p) << text;
  };
  // A non-finite entry (null is how a JSON writer spells NaN) in the first ok Hessian.
  with("\"h\":[", "\"h\":[null,");
  EXPECT_NE(ErrorOf(p, f, f.triplets).find(".h"), std::string::npos);
  with("\"version\": 1", "\"version\": 99");
  EXPECT_NE(ErrorOf(p, f, f.triplets).find("version"), std::string::npos);
  with("\"status\":\"ok\"", "\"status\":\"fine\"");
  EXPECT_NE(ErrorOf(p, f, f.triplets).find("unknown status"), std::string::npos);
  fs::remove(p);
}

// Motions of five views: 30 x 30 h and a 30-vector newton_step survive the round trip; a file
// written for the triplets does not read against them; files of the triplet-only versions
// (key "triplet_index") still read.
TEST(LocalHessianIo, FiveViewMotionsRoundTripAndAreCheckedAgainstTheMotions) {
  const Fixture f = Make();
  LocalMotionOptions o;
  o.views = 5;
  const std::vector<LocalMotion> motions = SelectLocalMotions(f.rec, PosesOf(f.rec), o);
  ASSERT_FALSE(motions.empty());
  const LocalHessianResult result = ComputeLocalHessians(f.rec, motions, PaperTripletLocalHessianOptions());
  ASSERT_EQ(result.num_ok(), static_cast<int>(motions.size()));
  const fs::path p = fs::temp_directory_path() / "pgba_lh_motions.json";
  WriteLocalHessians(p, f.rec, result);
  const LocalHessianResult back = ReadLocalHessians(p, f.rec, motions);
  ASSERT_EQ(back.hessians.size(), motions.size());
  for (size_t i = 0; i < motions.size(); ++i) {
    const LocalHessian &a = result.hessians[i], &b = back.hessians[i];
    ASSERT_EQ(b.h.rows(), 30);
    EXPECT_EQ((a.h.Dense() - b.h.Dense()).cwiseAbs().maxCoeff(), 0.0) << i;
    EXPECT_EQ(a.newton_step, b.newton_step) << i;
    EXPECT_EQ(b.local_poses.size(), 5u);
    Eigen::MatrixXd V;
    Eigen::VectorXd D;
    b.Factor(&V, &D);
    const Eigen::MatrixXd W = D.asDiagonal() * V;
    EXPECT_LT((W.transpose() * W - a.h.Dense()).norm(), 1e-9 * a.h.Dense().norm()) << i;
  }
  // Against the triplets of the same scene (another motion set): an error naming the file.
  std::vector<LocalMotion> as_triplets = f.triplets;
  as_triplets.resize(motions.size());
  std::string error;
  try {
    ReadLocalHessians(p, f.rec, as_triplets);
  } catch (const InputError& e) {
    error = e.what();
  }
  EXPECT_NE(error.find(p.string()), std::string::npos) << error;
  EXPECT_NE(error.find("hessians[0]"), std::string::npos) << error;
  // The key of the triplet-only files.
  nlohmann::json j = nlohmann::json::parse(ReadAll(p));
  for (nlohmann::json& e : j["hessians"]) {
    e["triplet_index"] = e["motion_index"];
    e.erase("motion_index");
  }
  std::ofstream(p) << j.dump();
  EXPECT_EQ(ReadLocalHessians(p, f.rec, motions).num_ok(), result.num_ok());
  fs::remove(p);
}

// newton_step (-h^-1 g, global residual offset) is stored; an entry without it reads as
// zero (paper eq. 5), a malformed one is an error naming the entry.
TEST(LocalHessianIo, NewtonStepIsOptionalOnReading) {
  Fixture f = Make();
  f.result.hessians[0].newton_step.setConstant(1e-6);
  const fs::path p = fs::temp_directory_path() / "pgba_lh_newton.json";
  WriteLocalHessians(p, f.rec, f.result);
  EXPECT_EQ(ReadLocalHessians(p, f.rec, f.triplets).hessians[0].newton_step, f.result.hessians[0].newton_step);
  nlohmann::json j = nlohmann::json::parse(ReadAll(p));
  for (nlohmann::json& e : j["hessians"]) e.erase("newton_step");
  std::ofstream(p) << j.dump();
  const LocalHessianResult old = ReadLocalHessians(p, f.rec, f.triplets);
  EXPECT_EQ(old.num_ok(), f.result.num_ok());
  EXPECT_TRUE(old.hessians[0].newton_step.isZero(0.0));
  j["hessians"][0]["newton_step"] = {1.0, 2.0};
  std::ofstream(p) << j.dump();
  EXPECT_NE(ErrorOf(p, f, f.triplets).find("hessians[0].newton_step"), std::string::npos);
  fs::remove(p);
}

}  // namespace
}  // namespace pgba
