// Calibration JSON (pgba/io/calibration_json.h): the same cameras as the equivalent COLMAP
// cameras.txt, the optional image -> camera map, and a one-line error naming the file for
// every malformed input.
#include "pgba/io/calibration_json.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "pgba/io/colmap_text.h"
#include "pgba/util/error.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

class CalibrationJsonTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("pgba_calib_json_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Write(const std::string& name, const std::string& content) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << content;
    return path;
  }
  std::string ErrorOf(const std::string& content) {
    const std::string path = Write("calib.json", content);
    try {
      ReadCalibrationJson(path);
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      return what;
    }
    return "";
  }
  fs::path dir_;
};

TEST_F(CalibrationJsonTest, SameCamerasAsTheEquivalentCamerasTxt) {
  const std::string txt = Write("cameras.txt",
                                "# cameras\n1 PINHOLE 3072 2048 2759.48 2764.16 1520.69 1006.81\n"
                                "2 SIMPLE_RADIAL 640 480 500 320 240 0.01\n");
  const std::string json = Write("calib.json", R"({"cameras": [
      {"camera_id": 1, "model": "PINHOLE", "width": 3072, "height": 2048, "params": [2759.48, 2764.16, 1520.69, 1006.81]},
      {"camera_id": 2, "model": "SIMPLE_RADIAL", "width": 640, "height": 480, "params": [500, 320, 240, 0.01]}],
    "images": {"a.jpg": 1, "b.jpg": 2}})");
  const std::map<uint32_t, Camera> expected = ReadColmapCameras(txt);
  const CalibrationFile got = ReadCalibrationJson(json);
  ASSERT_EQ(got.cameras.size(), expected.size());
  for (const auto& [id, cam] : expected) {
    const Camera& c = got.cameras.at(id);
    EXPECT_EQ(c.model, cam.model);
    EXPECT_EQ(c.width, cam.width);
    EXPECT_EQ(c.height, cam.height);
    EXPECT_EQ(c.params, cam.params);
  }
  EXPECT_EQ(got.camera_of.at("a.jpg"), 1u);
  EXPECT_EQ(got.camera_of.at("b.jpg"), 2u);
}

TEST_F(CalibrationJsonTest, ImagesMapIsOptional) {
  const CalibrationFile got = ReadCalibrationJson(
      Write("c.json", R"({"cameras": [{"camera_id": 7, "model": "SIMPLE_PINHOLE", "width": 100, "height": 80,
                                       "params": [90, 50, 40]}]})"));
  EXPECT_EQ(got.cameras.size(), 1u);
  EXPECT_TRUE(got.camera_of.empty());
}

TEST_F(CalibrationJsonTest, MalformedInputNamesTheFileAndTheProblem) {
  const std::string cam = R"("camera_id": 1, "model": "PINHOLE", "width": 640, "height": 480)";
  EXPECT_NE(ErrorOf("{not json").find("malformed JSON"), std::string::npos);
  EXPECT_NE(ErrorOf("{}").find("missing \"cameras\""), std::string::npos);
  EXPECT_NE(ErrorOf(R"({"cameras": []})").find("non-empty array"), std::string::npos);
  EXPECT_NE(ErrorOf(R"({"cameras": [{"model": "PINHOLE"}]})").find("cameras[0]: missing \"camera_id\""),
            std::string::npos);
  EXPECT_NE(ErrorOf(R"({"cameras": [{"camera_id": 1, "model": "FISHEYE9", "width": 1, "height": 1, "params": []}]})")
                .find("unknown camera model"),
            std::string::npos);
  EXPECT_FALSE(ErrorOf(R"({"cameras": [{)" + cam + R"(, "params": [500, 500, 320]}]})").empty());  // 3 of 4 params
  EXPECT_NE(ErrorOf(R"({"cameras": [{)" + cam + R"(, "params": [500, "x", 320, 240]}]})").find("array of numbers"),
            std::string::npos);
  EXPECT_NE(ErrorOf(R"({"cameras": [{)" + cam + R"(, "params": [500, 500, 320, 240]}, {)" + cam +
                    R"(, "params": [500, 500, 320, 240]}]})")
                .find("listed twice"),
            std::string::npos);
  EXPECT_NE(ErrorOf(R"({"cameras": [{)" + cam + R"(, "params": [500, 500, 320, 240]}], "images": {"a.png": 3}})")
                .find("camera 3 is not in"),
            std::string::npos);
}

}  // namespace
}  // namespace pgba
