// loop_pairs.txt: exact round trip, strict parsing with file:line errors, atomic writes.
#include "pgba/io/loop_pairs.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "pgba/util/error.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

class LoopPairsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("pgba_loop_pairs_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Write(const std::string& content) {
    const std::string path = (dir_ / "loop_pairs.txt").string();
    std::ofstream(path) << content;
    return path;
  }
  // The InputError message for `content`, "" if it parsed.
  std::string ErrorOf(const std::string& content) {
    const std::string path = Write(content);
    try {
      ReadLoopPairs(path);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

  fs::path dir_;
};

TEST_F(LoopPairsTest, RoundTripIsExact) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 5616.0);
  std::vector<LoopCorrespondence> pairs;
  for (int k = 0; k < 200; ++k)
    pairs.push_back({"img_" + std::to_string(k % 3) + ".jpg",
                     {u(rng), u(rng)},
                     "img_" + std::to_string(90 + k % 3),
                     {u(rng), u(rng)}});
  pairs.push_back({"a", {-0.0, 1e-300}, "b", {1.0 / 3.0, 12345.678901234567}});
  const std::string path = (dir_ / "out" / "loop_pairs.txt").string();
  WriteLoopPairs(pairs, path);
  const auto back = ReadLoopPairs(path);
  ASSERT_EQ(back.size(), pairs.size());
  for (size_t k = 0; k < pairs.size(); ++k) {
    EXPECT_EQ(back[k].name_i, pairs[k].name_i);
    EXPECT_EQ(back[k].name_j, pairs[k].name_j);
    EXPECT_EQ(back[k].xy_i, pairs[k].xy_i);  // bit-exact
    EXPECT_EQ(back[k].xy_j, pairs[k].xy_j);
  }
  // No temporary left behind.
  for (const auto& entry : fs::directory_iterator(dir_ / "out")) EXPECT_EQ(entry.path().filename(), "loop_pairs.txt");
}

TEST_F(LoopPairsTest, CommentsBlankLinesAndCrlfAreAccepted) {
  const auto pairs = ReadLoopPairs(Write("# header\n\n  a.jpg 1 2 b.jpg 3.5 4e2\r\n   # indented comment\n"));
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].name_i, "a.jpg");
  EXPECT_EQ(pairs[0].xy_j, Eigen::Vector2d(3.5, 400.0));
  EXPECT_TRUE(ReadLoopPairs(Write("")).empty());
}

TEST_F(LoopPairsTest, MalformedLinesNameFileAndLine) {
  const std::string file = (dir_ / "loop_pairs.txt").string();
  const std::string good = "a 1 2 b 3 4\n";
  struct Case {
    std::string content;
    int line;
    std::string mentions;
  };
  const std::vector<Case> cases = {
      {good + "a 1 2 b 3\n", 2, "6 fields"},             // truncated
      {good + good + "a 1 2 b 3 4 5\n", 3, "6 fields"},  // trailing garbage
      {"# c\na x 2 b 3 4\n", 2, "x_i"},                  // not a number
      {"a 1 2y b 3 4\n", 1, "y_i"},                      // trailing characters
      {"a 1 2 b nan 4\n", 1, "non-finite"},              // NaN
      {"a 1 2 b 3 inf\n", 1, "non-finite"},              // Inf
      {"a 1 2 b 3 1e999\n", 1, "invalid number"},        // overflow
      {"a 1 2 a 3 4\n", 1, "two different images"},      // self pair
      {good + "\x01\x02\x03 garbage\n", 2, "6 fields"},  // binary junk
  };
  for (const Case& c : cases) {
    const std::string err = ErrorOf(c.content);
    EXPECT_NE(err.find(file + ":" + std::to_string(c.line) + ":"), std::string::npos) << c.content << " -> " << err;
    EXPECT_NE(err.find(c.mentions), std::string::npos) << c.content << " -> " << err;
  }
}

TEST_F(LoopPairsTest, RandomGarbageNeverCrashes) {
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<int> byte(0, 255), len(0, 300);
  for (int trial = 0; trial < 200; ++trial) {
    std::string junk;
    for (int k = len(rng); k > 0; --k) junk.push_back(static_cast<char>(byte(rng)));
    const std::string path = Write(junk);
    try {
      ReadLoopPairs(path);  // may legitimately parse (e.g. only blank lines)
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path + ":", 0), 0u) << e.what();
    }
  }
}

TEST_F(LoopPairsTest, MissingFileAndUnrepresentableNames) {
  const std::string missing = (dir_ / "nope.txt").string();
  try {
    ReadLoopPairs(missing);
    FAIL() << "no error for a missing file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos);
  }
  const std::string path = (dir_ / "w.txt").string();
  EXPECT_THROW(WriteLoopPairs({{"has space.jpg", {1, 2}, "b", {3, 4}}}, path), InputError);
  EXPECT_THROW(WriteLoopPairs({{"", {1, 2}, "b", {3, 4}}}, path), InputError);
  EXPECT_FALSE(fs::exists(path));
}

}  // namespace
}  // namespace pgba
