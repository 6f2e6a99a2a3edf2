// GCP file: parsing (any record order, optional sigma, comments), one-line file:line errors
// for every malformed input, write -> read round trip.
#include "pgba/io/gcp_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "pgba/util/error.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

class GcpFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("pgba_gcp_file_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Write(const std::string& content) {
    const std::string path = (dir_ / "gcp.txt").string();
    std::ofstream(path) << content;
    return path;
  }
  // The InputError message for `content`, "" if it parsed.
  std::string ErrorOf(const std::string& content) {
    const std::string path = Write(content);
    try {
      ReadGcpFile(path);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

TEST_F(GcpFileTest, ParsesRecordsInAnyOrder) {
  const std::string path = Write(
      "# survey of 2024\n"
      "OBS b img2.jpg 10.5 20.25\n"
      "GCP a 1 2 3 0.02\n"
      "\n"
      "GCP b -4.5 5e3 6\n"
      "OBS a img1.jpg 100 200\n"
      "OBS a img2.jpg 101 201\n");
  const std::vector<GcpFileEntry> g = ReadGcpFile(path);
  ASSERT_EQ(g.size(), 2u);
  EXPECT_EQ(g[0].name, "a");
  EXPECT_EQ(g[0].X, Eigen::Vector3d(1, 2, 3));
  EXPECT_DOUBLE_EQ(g[0].sigma, 0.02);
  ASSERT_EQ(g[0].observations.size(), 2u);
  EXPECT_EQ(g[0].observations[1].image_name, "img2.jpg");
  EXPECT_EQ(g[0].observations[1].xy, Eigen::Vector2d(101, 201));
  EXPECT_EQ(g[1].X, Eigen::Vector3d(-4.5, 5000, 6));
  EXPECT_EQ(g[1].sigma, 0.0);  // none given: the caller's default applies
  ASSERT_EQ(g[1].observations.size(), 1u);
  EXPECT_EQ(g[1].observations[0].xy, Eigen::Vector2d(10.5, 20.25));
  EXPECT_EQ(g[1].observations[0].line, 2);
}

TEST_F(GcpFileTest, MalformedInputNamesFileAndLine) {
  const std::string path = (dir_ / "gcp.txt").string();
  struct Case {
    std::string content, line, what;
  };
  const Case cases[] = {
      {"GCP a 1 2\n", ":1:", "fields"},
      {"GCP a 1 2 3 0.1 9\n", ":1:", "fields"},
      {"GCP a 1 x 3\n", ":1:", "Y"},
      {"GCP a 1 2 nan\n", ":1:", "Z"},
      {"GCP a 1 2 3 0\n", ":1:", "sigma"},
      {"GCP a 1 2 3 -1\n", ":1:", "sigma"},
      {"GCP a 1 2 3\nGCP a 4 5 6\n", ":2:", "duplicate"},
      {"GCP a 1 2 3\nOBS a img.jpg 1\n", ":2:", "fields"},
      {"GCP a 1 2 3\nOBS a img.jpg 1 inf\n", ":2:", "y"},
      {"GCP a 1 2 3\n# c\nOBS z img.jpg 1 2\n", ":3:", "'z'"},
      {"GCP a 1 2 3\nPOINT a 1 2 3\n", ":2:", "unknown record"},
      {"# nothing\n", ": ", "no GCP"},
  };
  for (const Case& c : cases) {
    const std::string e = ErrorOf(c.content);
    EXPECT_NE(e.find(path + c.line), std::string::npos) << c.content << " -> " << e;
    EXPECT_NE(e.find(c.what), std::string::npos) << c.content << " -> " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
  EXPECT_NE(ErrorOf("").find("no GCP"), std::string::npos);
}

TEST_F(GcpFileTest, MissingFileIsInputError) {
  EXPECT_THROW(ReadGcpFile((dir_ / "absent.txt").string()), InputError);
}

TEST_F(GcpFileTest, WriteReadRoundTripIsExact) {
  std::vector<GcpFileEntry> in(2);
  in[0].name = "p1";
  in[0].X = Eigen::Vector3d(651234.123456789, 5401234.987654321, 312.0625);
  in[0].sigma = 0.015;
  in[0].observations = {{"a.jpg", Eigen::Vector2d(1.0 / 3.0, 2.0 / 7.0), 0}, {"b.jpg", Eigen::Vector2d(5, 6), 0}};
  in[1].name = "p2";
  in[1].X = Eigen::Vector3d(-1e-7, 0, 1e7);
  const std::string path = (dir_ / "out" / "gcp.txt").string();
  fs::create_directories(dir_ / "out");
  WriteGcpFile(in, path);
  const std::vector<GcpFileEntry> out = ReadGcpFile(path);
  ASSERT_EQ(out.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(out[i].name, in[i].name);
    EXPECT_EQ(out[i].X, in[i].X);
    EXPECT_EQ(out[i].sigma, in[i].sigma);
    ASSERT_EQ(out[i].observations.size(), in[i].observations.size());
    for (size_t k = 0; k < in[i].observations.size(); ++k) {
      EXPECT_EQ(out[i].observations[k].image_name, in[i].observations[k].image_name);
      EXPECT_EQ(out[i].observations[k].xy, in[i].observations[k].xy);
    }
  }
}

}  // namespace
}  // namespace pgba
