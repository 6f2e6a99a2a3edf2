// Outputs apart from inputs (util/output_path.h): an output folder that is an input, lies
// inside one, or would replace an entry holding one is refused; other spellings of the same
// folder (a trailing "/", "..", a symbolic link) are caught as well.
#include "pgba/util/output_path.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "pgba/util/error.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

class OutputPathTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("pgba_output_path_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "ds" / "images");
    std::ofstream(dir_ / "ds" / "images" / "a.jpg") << "a";
    std::ofstream(dir_ / "ds" / "cameras.txt") << "1 PINHOLE 10 10 10 10 5 5\n";
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The message of the InputError CheckOutputDirApartFromInputs throws, "" if none.
  std::string DirProblem(const std::string& out, const std::vector<NamedInput>& inputs) const {
    try {
      CheckOutputDirApartFromInputs(out, {"images", "cameras.txt", "gt"}, inputs);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

TEST_F(OutputPathTest, RefusesAnOutputThatIsContainsOrLiesInsideAnInput) {
  const std::string ds = (dir_ / "ds").string(), images = (dir_ / "ds" / "images").string();
  EXPECT_NE(DirProblem(ds, {{"--images", images}}).find(ds + ": the output " + ds + "/images would replace the input --images"),
            std::string::npos);
  EXPECT_NE(DirProblem(ds + "/", {{"--images", images}}).find("would replace the input --images"), std::string::npos);
  EXPECT_NE(DirProblem((dir_ / "ds" / "images" / ".." ).string(), {{"--images", images}}).find("would replace"),
            std::string::npos);
  EXPECT_NE(DirProblem(images, {{"--images", images}}).find("the output folder is the input --images"),
            std::string::npos);
  EXPECT_NE(DirProblem(images + "/out", {{"--images", images}}).find("lies inside the input --images"),
            std::string::npos);
  EXPECT_NE(DirProblem(ds, {{"--cameras", ds + "/cameras.txt"}}).find("would replace the input --cameras"),
            std::string::npos);
  // Through a symbolic link to the dataset.
  fs::create_directory_symlink(dir_ / "ds", dir_ / "link");
  EXPECT_NE(DirProblem((dir_ / "link").string(), {{"--images", images}}).find("would replace the input --images"),
            std::string::npos);
  // Apart: another folder, an input inside the output under a name it does not write, no input.
  EXPECT_EQ(DirProblem((dir_ / "out").string(), {{"--images", images}}), "");
  fs::create_directories(dir_ / "ws" / "photos");
  EXPECT_EQ(DirProblem((dir_ / "ws").string(), {{"--images", (dir_ / "ws" / "photos").string()}}), "");
  EXPECT_EQ(DirProblem(ds, {{"--calib", ""}}), "");
  // A file output.
  EXPECT_THROW(CheckOutputFileApartFromInputs(images + "/a.jpg", {{"--images", images}}), InputError);
  EXPECT_THROW(CheckOutputFileApartFromInputs(ds + "/cameras.txt", {{"--calib", ds + "/cameras.txt"}}), InputError);
  EXPECT_NO_THROW(CheckOutputFileApartFromInputs((dir_ / "m.json").string(), {{"--images", images}}));
  EXPECT_THROW(RequireOutputPath("", "--out"), InputError);
}

}  // namespace
}  // namespace pgba
