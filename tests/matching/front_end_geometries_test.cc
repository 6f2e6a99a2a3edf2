// Reading the front end's verified geometries back for the view graph: what the matching
// stage wrote comes back unchanged, and a file that does not fit the tracks (an image they
// do not have, a pair twice, a malformed line) is an InputError naming the file.
#include "matching/front_end_geometries.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "pgba/geometry/rotation.h"
#include "pgba/io/two_view_geometries.h"
#include "pgba/util/error.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

Reconstruction TracksOfImages(std::initializer_list<uint32_t> ids) {
  Reconstruction r;
  for (uint32_t id : ids) {
    Image im;
    im.image_id = id;
    im.name = "im" + std::to_string(id) + ".png";
    r.images[id] = im;
  }
  return r;
}

TwoViewGeometry Pair(uint32_t a, uint32_t b) {
  TwoViewGeometry g;
  g.image_id1 = a;
  g.image_id2 = b;
  g.R_21 = ExpSO3(Eigen::Vector3d(0.1, -0.2, 0.05));
  g.t_21 = Eigen::Vector3d(1, 2, -0.5).normalized();
  g.num_inliers = 120;
  g.num_tracks = 100;
  g.median_triangulation_angle_deg = 4.5;
  return g;
}

class FrontEndGeometries : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("pgba_fe_geometries_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // The InputError message of reading `text` as the file against images 1, 2, 3.
  std::string ErrorOf(const std::string& text) {
    const std::string path = (dir_ / "two_view_geometries.txt").string();
    std::ofstream(path) << text;
    try {
      ReadFrontEndGeometries(path, TracksOfImages({1, 2, 3}));
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

TEST_F(FrontEndGeometries, WhatTheMatchingStageWroteComesBack) {
  const std::vector<TwoViewGeometry> written = {Pair(1, 2), Pair(3, 1)};
  EXPECT_EQ(FrontEndGeometriesPath("/ws"), "/ws/matching/two_view_geometries.txt");
  const std::string path = (dir_ / "g.txt").string();
  WriteTwoViewGeometries(written, path);
  const auto read = ReadFrontEndGeometries(path, TracksOfImages({1, 2, 3}));
  ASSERT_EQ(read.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(read[i].image_id1, written[i].image_id1);
    EXPECT_EQ(read[i].image_id2, written[i].image_id2);
    EXPECT_LT(RotationAngleDeg(read[i].R_21, written[i].R_21), 1e-12);
    EXPECT_LT((read[i].t_21 - written[i].t_21).norm(), 1e-15);
    EXPECT_EQ(read[i].num_inliers, 120);
    EXPECT_EQ(read[i].median_triangulation_angle_deg, 4.5);
  }
}

TEST_F(FrontEndGeometries, AFileThatDoesNotFitTheTracksNamesItself) {
  const std::string path = (dir_ / "two_view_geometries.txt").string();
  const std::string ok = "1 2 1 0 0 0 1 0 0 50 40 3.0\n";
  EXPECT_EQ(ErrorOf(ok), "");
  const std::string unknown = ErrorOf(ok + "2 7 1 0 0 0 0 1 0 50 40 3.0\n");
  EXPECT_NE(unknown.find(path), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("pair (2, 7): image 7 is not in the tracks"), std::string::npos) << unknown;
  EXPECT_NE(ErrorOf(ok + "2 1 1 0 0 0 1 0 0 50 40 3.0\n").find("listed twice"), std::string::npos);
  EXPECT_NE(ErrorOf("2 2 1 0 0 0 1 0 0 50 40 3.0\n").find("paired with itself"), std::string::npos);
  EXPECT_NE(ErrorOf("1 2 1 0 0 0 0 0 0 50 40 3.0\n").find("not a unit vector"), std::string::npos);
  EXPECT_NE(ErrorOf("1 2 1 0 0 0 1 0 0 -5 40 3.0\n").find("negative"), std::string::npos);
  // Malformed lines: the reader's "FILE:LINE: problem".
  const std::string short_line = ErrorOf("1 2 1 0 0 0 1 0 0 50\n");
  EXPECT_NE(short_line.find(path + ":1"), std::string::npos) << short_line;
  const std::string nan = ErrorOf("# comment\n1 2 nan 0 0 0 1 0 0 50 40 3.0\n");
  EXPECT_NE(nan.find(path + ":2"), std::string::npos) << nan;
}

}  // namespace
}  // namespace pgba
