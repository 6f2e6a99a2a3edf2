// BuildTriplets (and the EstimatePairs before it) promise a result independent of the thread
// count (triplets.h, view_graph.h). Checked on a synthetic orbit with noise and outliers:
// pairs.json and triplets.json written from a run on 1 thread and from runs on 2 threads are
// byte-identical (the JSON writer prints every double with round-trip precision, so equal
// bytes are equal bits), and the triplets are real ones (every image covered, relative
// rotations near the ground truth), so the comparison is not between two empty results.
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "pgba/geometry/rotation.h"
#include "pgba/io/workspace.h"
#include "synthetic/synthetic_scene.h"
#include "triplets/triplets.h"
#include "triplets/pair_estimation.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

std::string Slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Files {
  std::string pairs, triplets;
  size_t num_triplets = 0;
};

Files RunOn(int threads, const SyntheticScene& scene, const fs::path& dir, double* max_rot_err_deg) {
  tbb::global_control c(tbb::global_control::max_allowed_parallelism, threads);
  const std::vector<TwoViewGeometry> pairs = EstimatePairs(scene.input, PairOptions{});
  TripletStats stats;
  const std::vector<LocalMotion> triplets = BuildTriplets(scene.input, pairs, TripletOptions{}, &stats);
  EXPECT_EQ(stats.images_covered, static_cast<int>(scene.gt.images.size()));
  for (const LocalMotion& t : triplets)
    for (int k = 1; k < 3; ++k) {
      const Pose& a = scene.gt.images.at(t.image_ids[0]).pose;
      const Pose& b = scene.gt.images.at(t.image_ids[k]).pose;
      *max_rot_err_deg = std::max(*max_rot_err_deg, RotationAngleDeg(t.local_poses[k].R() * t.local_poses[0].R().transpose(),
                                                                      b.R() * a.R().transpose()));
    }
  fs::create_directories(dir);
  WritePairs(dir / "pairs.json", scene.input, pairs);
  WriteTriplets(dir / "triplets.json", scene.input, triplets);
  return {Slurp(dir / "pairs.json"), Slurp(dir / "triplets.json"), triplets.size()};
}

TEST(TripletThreads, ByteIdenticalTripletsOnOneAndTwoThreads) {
  SyntheticOptions so;
  so.scenario = SyntheticScenario::kOrbit;
  so.seed = 11;
  so.noise_px = 0.5;
  so.outlier_fraction = 0.02;
  so.num_images = 36;  // 10 degrees apart: triangles of the view graph, not only open triplets
  so.num_points = 5000;
  const SyntheticScene scene = GenerateSyntheticScene(so);
  const fs::path dir = fs::temp_directory_path() / ("pgba_triplet_threads_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  double max_err = 0.0;
  const Files one = RunOn(1, scene, dir / "one", &max_err);
  ASSERT_GE(one.num_triplets, static_cast<size_t>(so.num_images));
  // Twice on two threads: the scheduling differs from run to run, the result must not.
  for (int run = 0; run < 2; ++run) {
    const Files two = RunOn(2, scene, dir / ("two" + std::to_string(run)), &max_err);
    EXPECT_EQ(one.pairs, two.pairs) << "run " << run;
    EXPECT_EQ(one.triplets, two.triplets) << "run " << run;
  }
  std::cout << one.num_triplets << " triplets, max relative rotation error " << max_err << " deg\n";
  EXPECT_LT(max_err, 0.4);  // measured 0.33 deg (0.5 px noise, 2% outliers)
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pgba
