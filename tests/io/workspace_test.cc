#include "pgba/io/workspace.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <random>
#include <sstream>

#include "pgba/geometry/rotation.h"
#include "pgba/util/error.h"

namespace pgba {
namespace {

namespace fs = std::filesystem;

class WorkspaceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("pgba_workspace_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::mt19937_64 rng(4);
    tracks_.cameras[1] = Camera();
    for (uint32_t id : {3u, 5u, 8u, 13u}) {
      Image im;
      im.image_id = id;
      im.name = "frame_" + std::to_string(id) + ".png";
      im.camera_id = 1;
      tracks_.images[id] = im;
    }
    for (uint64_t p = 10; p < 20; ++p) tracks_.points3D[p].point3D_id = p;
    std::normal_distribution<double> n(0.0, 1.0);
    for (auto [a, b] : {std::pair{3u, 5u}, {5u, 8u}, {3u, 13u}}) {
      TwoViewGeometry g;
      g.image_id1 = a;
      g.image_id2 = b;
      g.R_21 = RandomRotation(rng);
      g.t_21 = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
      g.num_tracks = 100 + a;
      g.num_inliers = 90 + b;
      g.median_triangulation_angle_deg = 3.0 + n(rng);
      pairs_.push_back(g);
    }
    for (auto ids : {std::array<uint32_t, 3>{3, 5, 8}, {5, 8, 13}}) {
      LocalMotion t;
      t.image_ids.assign(ids.begin(), ids.end());
      t.local_poses.resize(3);
      for (Pose& p : t.local_poses) p = Pose::FromRC(RandomRotation(rng), Eigen::Vector3d(n(rng), n(rng), n(rng)));
      t.track_ids = {10, 12, 19};
      t.rms_px = 0.4 + 0.1 * n(rng);
      t.global_to_local.s = 2.5;
      t.global_to_local.R = RandomRotation(rng);
      t.global_to_local.t = Eigen::Vector3d(n(rng), n(rng), n(rng));
      triplets_.push_back(t);
    }
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Slurp(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  void Spit(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }
  // Replaces the first occurrence of `from` in the file.
  void Edit(const fs::path& p, const std::string& from, const std::string& to) {
    std::string text = Slurp(p);
    const size_t pos = text.find(from);
    ASSERT_NE(pos, std::string::npos) << from;
    text.replace(pos, from.size(), to);
    Spit(p, text);
  }
  // The InputError message of `f`, or "" if none was thrown.
  template <typename F>
  std::string ErrorOf(F f) {
    try {
      f();
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

  fs::path dir_;
  Reconstruction tracks_;
  std::vector<TwoViewGeometry> pairs_;
  std::vector<LocalMotion> triplets_;
};

TEST_F(WorkspaceTest, PairsRoundTrip) {
  const fs::path path = WorkspacePairsPath(dir_);
  WritePairs(path, tracks_, pairs_);
  const std::vector<TwoViewGeometry> read = ReadPairs(path, tracks_);
  ASSERT_EQ(read.size(), pairs_.size());
  for (size_t k = 0; k < read.size(); ++k) {
    EXPECT_EQ(read[k].image_id1, pairs_[k].image_id1);
    EXPECT_EQ(read[k].image_id2, pairs_[k].image_id2);
    EXPECT_EQ(read[k].R_21, pairs_[k].R_21);  // bit-exact
    EXPECT_EQ(read[k].t_21, pairs_[k].t_21);
    EXPECT_EQ(read[k].num_tracks, pairs_[k].num_tracks);
    EXPECT_EQ(read[k].num_inliers, pairs_[k].num_inliers);
    EXPECT_EQ(read[k].median_triangulation_angle_deg, pairs_[k].median_triangulation_angle_deg);
  }
  // One entry per line, names readable, nothing left behind by the atomic write.
  const std::string text = Slurp(path);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), static_cast<long>(pairs_.size() + 2));
  EXPECT_NE(text.find("\"frame_13.png\""), std::string::npos);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(WorkspaceTest, TripletsRoundTrip) {
  const fs::path path = WorkspaceTripletsPath(dir_);
  WriteTriplets(path, tracks_, triplets_);
  const std::vector<LocalMotion> read = ReadTriplets(path, tracks_);
  ASSERT_EQ(read.size(), triplets_.size());
  for (size_t k = 0; k < read.size(); ++k) {
    EXPECT_EQ(read[k].image_ids, triplets_[k].image_ids);
    for (int v = 0; v < 3; ++v) {
      // q is renormalised on reading (Pose::FromQt): equal to the last bit or two.
      EXPECT_LT((read[k].local_poses[v].q().coeffs() - triplets_[k].local_poses[v].q().coeffs()).norm(), 1e-15);
      EXPECT_EQ(read[k].local_poses[v].t(), triplets_[k].local_poses[v].t());
    }
    EXPECT_EQ(read[k].track_ids, triplets_[k].track_ids);
    EXPECT_EQ(read[k].rms_px, triplets_[k].rms_px);
    EXPECT_EQ(read[k].global_to_local.s, triplets_[k].global_to_local.s);
    EXPECT_EQ(read[k].global_to_local.R, triplets_[k].global_to_local.R);
    EXPECT_EQ(read[k].global_to_local.t, triplets_[k].global_to_local.t);
  }
  // Overwriting replaces the file.
  triplets_.pop_back();
  WriteTriplets(path, tracks_, triplets_);
  EXPECT_EQ(ReadTriplets(path, tracks_).size(), 1u);
}

TEST_F(WorkspaceTest, VersionMismatchIsInputError) {
  const fs::path path = WorkspacePairsPath(dir_);
  WritePairs(path, tracks_, pairs_);
  Edit(path, "\"version\": 1", "\"version\": 7");
  const std::string e = ErrorOf([&] { ReadPairs(path, tracks_); });
  EXPECT_NE(e.find(path.string()), std::string::npos) << e;
  EXPECT_NE(e.find("version 7"), std::string::npos) << e;
  // A triplets file read as pairs: wrong format.
  WriteTriplets(WorkspaceTripletsPath(dir_), tracks_, triplets_);
  EXPECT_NE(ErrorOf([&] { ReadPairs(WorkspaceTripletsPath(dir_), tracks_); }).find("pgba_pairs"), std::string::npos);
}

TEST_F(WorkspaceTest, UnknownImageNameIsInputError) {
  const fs::path pairs_path = WorkspacePairsPath(dir_), triplets_path = WorkspaceTripletsPath(dir_);
  WritePairs(pairs_path, tracks_, pairs_);
  WriteTriplets(triplets_path, tracks_, triplets_);
  Reconstruction other = tracks_;
  other.images[8].name = "renamed.png";
  const std::string e = ErrorOf([&] { ReadPairs(pairs_path, other); });
  EXPECT_EQ(e, pairs_path.string() + ": pairs[1]: unknown image name 'frame_8.png' (workspace of another model?)");
  EXPECT_NE(ErrorOf([&] { ReadTriplets(triplets_path, other); }).find("triplets[0]: unknown image name"),
            std::string::npos);
  // Same names, different ids.
  Reconstruction shuffled = tracks_;
  std::swap(shuffled.images[3].name, shuffled.images[5].name);
  EXPECT_NE(ErrorOf([&] { ReadPairs(pairs_path, shuffled); }).find("has id"), std::string::npos);
  // A track that is not in the model.
  Reconstruction fewer = tracks_;
  fewer.points3D.erase(12);
  EXPECT_NE(ErrorOf([&] { ReadTriplets(triplets_path, fewer); }).find("track id 12"), std::string::npos);
}

TEST_F(WorkspaceTest, MalformedFilesAreInputErrors) {
  const fs::path path = WorkspacePairsPath(dir_);
  EXPECT_NE(ErrorOf([&] { ReadPairs(path, tracks_); }).find("file not found"), std::string::npos);
  WritePairs(path, tracks_, pairs_);
  const std::string good = Slurp(path);
  // Truncated JSON: the line of the problem is named.
  Spit(path, good.substr(0, good.size() / 2));
  std::string e = ErrorOf([&] { ReadPairs(path, tracks_); });
  EXPECT_NE(e.find("malformed JSON"), std::string::npos) << e;
  EXPECT_NE(e.find(path.string() + ":"), std::string::npos) << e;
  // Not a rotation (the writer does not validate, the reader does).
  std::vector<TwoViewGeometry> bad = pairs_;
  bad[2].R_21 *= 2.0;
  WritePairs(path, tracks_, bad);
  EXPECT_EQ(ErrorOf([&] { ReadPairs(path, tracks_); }), path.string() + ": pairs[2].R_21: not a rotation matrix");
  Spit(path, good);
  Edit(path, "\"num_inliers\":", "\"num_inliers\":\"many\",\"x\":");
  EXPECT_NE(ErrorOf([&] { ReadPairs(path, tracks_); }).find("expected an integer"), std::string::npos);
  Spit(path, good);
  Edit(path, "\"t_21\":[", "\"t_21\":[null,");
  EXPECT_NE(ErrorOf([&] { ReadPairs(path, tracks_); }).find("t_21"), std::string::npos);
  Spit(path, "[1, 2]");
  EXPECT_NE(ErrorOf([&] { ReadPairs(path, tracks_); }).find("not a JSON object"), std::string::npos);
  // Writing an image id the model does not know.
  pairs_[0].image_id2 = 77;
  EXPECT_NE(ErrorOf([&] { WritePairs(path, tracks_, pairs_); }).find("image id 77"), std::string::npos);
}

TEST_F(WorkspaceTest, BadTripletValues) {
  const fs::path path = WorkspaceTripletsPath(dir_);
  WriteTriplets(path, tracks_, triplets_);
  const std::string good = Slurp(path);
  Edit(path, "\"s\":2.5", "\"s\":-2.5");
  EXPECT_NE(ErrorOf([&] { ReadTriplets(path, tracks_); }).find("scale must be positive"), std::string::npos);
  Spit(path, good);
  Edit(path, "[\"frame_3.png\",\"frame_5.png\",\"frame_8.png\"]", "[\"frame_3.png\",\"frame_3.png\",\"frame_8.png\"]");
  Edit(path, "\"image_ids\":[3,5,8]", "\"image_ids\":[3,3,8]");
  EXPECT_NE(ErrorOf([&] { ReadTriplets(path, tracks_); }).find("repeated image"), std::string::npos);
}

// motions.json: motions of any N >= 3 views, the start's misfit and the poses they were
// linearised at, read back bit for bit (q to its last bit or two); a motion of fewer than three
// views, or a triplets file read as motions, is an InputError naming the file.
TEST_F(WorkspaceTest, MotionsRoundTripWithTheirStart) {
  WorkspaceMotions motions;
  LocalMotion four = triplets_[0];
  four.image_ids.push_back(13);
  four.local_poses.push_back(Pose::FromRC(ExpSO3(Eigen::Vector3d(0.3, -0.1, 0.2)), Eigen::Vector3d(0.1, 0.2, 0.3)));
  motions.motions = {four, triplets_[1]};
  motions.triplet_rotation_misfit = 1065.25;
  motions.linearization_poses[5] = triplets_[1].local_poses[2];
  motions.linearization_poses[13] = four.local_poses[3];
  const fs::path path = WorkspaceMotionsPath(dir_);
  WriteMotions(path, tracks_, motions);
  const WorkspaceMotions read = ReadMotions(path, tracks_);
  ASSERT_EQ(read.motions.size(), 2u);
  for (size_t k = 0; k < 2; ++k) {
    const LocalMotion& a = read.motions[k];
    const LocalMotion& b = motions.motions[k];
    EXPECT_EQ(a.image_ids, b.image_ids);
    ASSERT_EQ(a.local_poses.size(), b.local_poses.size());
    for (size_t v = 0; v < a.local_poses.size(); ++v) {
      EXPECT_LT((a.local_poses[v].q().coeffs() - b.local_poses[v].q().coeffs()).norm(), 1e-15);
      EXPECT_EQ(a.local_poses[v].t(), b.local_poses[v].t());
    }
    EXPECT_EQ(a.track_ids, b.track_ids);
    EXPECT_EQ(a.rms_px, b.rms_px);
    EXPECT_EQ(a.global_to_local.R, b.global_to_local.R);
    EXPECT_EQ(a.global_to_local.t, b.global_to_local.t);
  }
  EXPECT_EQ(read.triplet_rotation_misfit, 1065.25);
  ASSERT_EQ(read.linearization_poses.size(), 2u);
  EXPECT_EQ(read.linearization_poses.at(13).t(), four.local_poses[3].t());
  EXPECT_EQ(read.linearization_poses.at(5).t(), triplets_[1].local_poses[2].t());

  const std::string good = Slurp(path);
  Edit(path, "\"image_ids\":[5,8,13]", "\"image_ids\":[5,8]");
  EXPECT_EQ(ErrorOf([&] { ReadMotions(path, tracks_); }),
            path.string() + ": motions[1]: \"images\", \"image_ids\" and \"local_poses\" must hold the same number "
                            "(>= 3) of entries");
  Spit(path, good);
  Edit(path, "\"image_id\":13", "\"image_id\":5");
  EXPECT_NE(ErrorOf([&] { ReadMotions(path, tracks_); }).find("linearization_poses[1]: image 'frame_13.png' has id 13"),
            std::string::npos);
  WriteTriplets(WorkspaceTripletsPath(dir_), tracks_, triplets_);
  EXPECT_NE(ErrorOf([&] { ReadMotions(WorkspaceTripletsPath(dir_), tracks_); }).find("pgba_motions"), std::string::npos);
  // A triplets file holds motions of exactly three views.
  EXPECT_NE(ErrorOf([&] { WriteTriplets(WorkspaceTripletsPath(dir_), tracks_, {four}); }).find("4 views"),
            std::string::npos);
}

}  // namespace
}  // namespace pgba
