// The features stage on a folder built here: good images, a non-image, a corrupt image, an
// image of the wrong size; the cache; calibration lookup and camera maps; fatal errors.
#include "features/extract_features.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "features/feature_file.h"
#include "features/feature_index.h"
#include "pgba/io/colmap_text.h"
#include "pgba/util/error.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

cv::Mat TexturedImage(int w, int h, uint64_t seed) {
  cv::Mat img(h, w, CV_8U);
  cv::RNG rng(seed);
  rng.fill(img, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(img, img, cv::Size(0, 0), 2.0);
  return img;
}

std::string ReadBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

class ExtractFeaturesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("pgba_extract_" + std::to_string(::getpid()) + "_" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    images_ = root_ / "set" / "images";
    ws_ = root_ / "ws";
    fs::remove_all(root_);
    fs::create_directories(images_);
    for (int i = 0; i < 3; ++i)
      cv::imwrite((images_ / ("im" + std::to_string(i) + ".png")).string(), TexturedImage(320, 240, 10 + i));
  }
  void TearDown() override { fs::remove_all(root_); }
  void WriteCameras(const fs::path& path, const std::string& lines) { std::ofstream(path) << lines; }

  fs::path root_;
  fs::path images_;
  fs::path ws_;
};

TEST_F(ExtractFeaturesTest, SkipsBadFilesWithReasonsAndCaches) {
  WriteCameras(root_ / "set" / "cameras.txt", "1 PINHOLE 320 240 300 300 160 120\n");  // found in the parent
  std::ofstream(images_ / "notes.txt") << "not an image\n";
  std::ofstream(images_ / "noise.jpg") << std::string(1000, 'x');  // .jpg name, no JPEG inside
  cv::imwrite((images_ / "broken.png").string(), TexturedImage(320, 240, 99));
  fs::resize_file(images_ / "broken.png", fs::file_size(images_ / "broken.png") / 2);  // truncated
  cv::imwrite((images_ / "big.png").string(), TexturedImage(400, 300, 7));             // wrong size
  std::ofstream(images_ / ".hidden") << "ignored";

  const FeatureExtractionResult r = ExtractFeatures(images_.string(), {}, ws_.string(), {});
  ASSERT_EQ(r.index.images.size(), 3u);
  for (uint32_t i = 0; i < 3; ++i) {
    EXPECT_EQ(r.index.images[i].image_id, i + 1);
    EXPECT_EQ(r.index.images[i].name, "im" + std::to_string(i) + ".png");
    EXPECT_GT(r.index.images[i].num_features, 50);
  }
  std::map<std::string, std::string> skipped;
  for (const SkippedImage& s : r.skipped) skipped[s.name] = s.reason;
  ASSERT_EQ(skipped.size(), 4u);
  EXPECT_NE(skipped.at("big.png").find("400x300"), std::string::npos) << skipped.at("big.png");
  EXPECT_NE(skipped.at("broken.png").find("cannot decode"), std::string::npos) << skipped.at("broken.png");
  EXPECT_NE(skipped.at("notes.txt").find("not an image"), std::string::npos);
  EXPECT_NE(skipped.at("noise.jpg").find("not an image"), std::string::npos);
  EXPECT_EQ(r.num_extracted, 3);
  EXPECT_NEAR(r.megapixels_extracted, 3 * 320 * 240 * 1e-6, 1e-9);

  // The index on disk is what the matcher reads.
  const FeatureIndex index = ReadFeatureIndex(ws_.string());
  ASSERT_EQ(index.images.size(), 3u);
  EXPECT_EQ(index.cameras.at(1).width, 320);
  const std::string before = ReadBytes(FeatureFilePath(ws_.string(), "im1.png"));

  // Re-run: everything from the cache, files unchanged.
  const FeatureExtractionResult again = ExtractFeatures(images_.string(), {}, ws_.string(), {});
  EXPECT_EQ(again.num_cached, 3);
  EXPECT_EQ(again.num_extracted, 0);
  EXPECT_EQ(ReadBytes(FeatureFilePath(ws_.string(), "im1.png")), before);

  // Other options invalidate the cache; a damaged cache file is recomputed.
  FeatureExtractionOptions opt;
  opt.sift.max_features = 40;
  const FeatureExtractionResult capped = ExtractFeatures(images_.string(), {}, ws_.string(), opt);
  EXPECT_EQ(capped.num_extracted, 3);
  EXPECT_EQ(capped.index.images[0].num_features, 40);
  fs::resize_file(FeatureFilePath(ws_.string(), "im0.png"), 30);
  const FeatureExtractionResult repaired = ExtractFeatures(images_.string(), {}, ws_.string(), opt);
  EXPECT_EQ(repaired.num_extracted, 1);
  EXPECT_EQ(repaired.num_cached, 2);
  EXPECT_EQ(ReadFeatureFile(FeatureFilePath(ws_.string(), "im0.png")).size(), 40u);
}

TEST_F(ExtractFeaturesTest, ResultsDoNotDependOnParallelism) {
  WriteCameras(images_ / "cameras.txt", "1 PINHOLE 320 240 300 300 160 120\n");  // in the folder itself
  FeatureExtractionOptions serial;
  serial.max_parallel_images = 1;
  ExtractFeatures(images_.string(), {}, (root_ / "ws1").string(), serial);
  ExtractFeatures(images_.string(), {}, (root_ / "ws2").string(), {});
  for (int i = 0; i < 3; ++i) {
    const std::string name = "im" + std::to_string(i) + ".png";
    EXPECT_EQ(ReadBytes(FeatureFilePath((root_ / "ws1").string(), name)),
              ReadBytes(FeatureFilePath((root_ / "ws2").string(), name)));
  }
}

TEST_F(ExtractFeaturesTest, CameraMapAssignsCamerasAndSkipsUnmapped) {
  const fs::path cams = root_ / "cams.txt";
  WriteCameras(cams, "1 PINHOLE 320 240 300 300 160 120\n2 SIMPLE_RADIAL 320 240 310 160 120 0.01\n");
  // Several cameras and no map: the run cannot know which image uses which.
  EXPECT_THROW(ExtractFeatures(images_.string(), {cams.string(), ""}, ws_.string(), {}), InputError);
  std::ofstream(root_ / "map.txt") << "# name camera\nim0.png 2\nim1.png 1\n";
  const FeatureExtractionResult r =
      ExtractFeatures(images_.string(), {cams.string(), (root_ / "map.txt").string()}, ws_.string(), {});
  ASSERT_EQ(r.index.images.size(), 2u);
  EXPECT_EQ(r.index.images[0].camera_id, 2u);
  EXPECT_EQ(r.index.images[1].camera_id, 1u);
  ASSERT_EQ(r.skipped.size(), 1u);
  EXPECT_EQ(r.skipped[0].name, "im2.png");
  // A map naming a camera that does not exist is an error in the map's file and line.
  std::ofstream(root_ / "bad_map.txt") << "im0.png 7\n";
  try {
    ExtractFeatures(images_.string(), {cams.string(), (root_ / "bad_map.txt").string()}, ws_.string(), {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad_map.txt:1"), std::string::npos) << e.what();
  }
}

TEST_F(ExtractFeaturesTest, FatalInputsAreInputErrors) {
  // No calibration next to the images and none given, and nothing to take a focal prior
  // from (with images, the cameras are EXIF priors: exif_focal_test.cc).
  fs::create_directories(root_ / "notes_only");
  std::ofstream(root_ / "notes_only" / "notes.txt") << "not an image\n";
  EXPECT_THROW(ExtractFeatures((root_ / "notes_only").string(), {}, ws_.string(), {}), InputError);
  WriteCameras(root_ / "set" / "cameras.txt", "1 PINHOLE 320 240 300 300 160 120\n");
  EXPECT_THROW(ExtractFeatures(images_.string(), {(root_ / "nope.txt").string(), ""}, ws_.string(), {}), InputError);
  // Empty folder, missing folder.
  fs::create_directories(root_ / "set" / "empty");
  try {
    ExtractFeatures((root_ / "set" / "empty").string(), {}, ws_.string(), {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ExtractFeatures((root_ / "missing").string(), {}, ws_.string(), {}), InputError);
  // Nothing usable: every image has the wrong size for the calibration.
  WriteCameras(root_ / "set" / "cameras.txt", "1 PINHOLE 640 480 300 300 320 240\n");
  EXPECT_THROW(ExtractFeatures(images_.string(), {}, ws_.string(), {}), InputError);
  // Matching without features.
  EXPECT_THROW(ReadFeatureIndex((root_ / "no_ws").string()), InputError);
}

// The index the matcher reads is an input like any other: a FIFO is refused (the reader
// opened it and blocked), the JSON is parsed strictly and every value is checked, each error
// naming images.json.
TEST_F(ExtractFeaturesTest, FeatureIndexIsReadStrictly) {
  FeatureIndex index;
  WriteCameras(root_ / "cameras.txt", "1 PINHOLE 320 240 300 300 160 120\n");
  index.cameras = ReadColmapCameras((root_ / "cameras.txt").string());
  for (uint32_t id : {1u, 2u}) index.images.push_back({id, "im" + std::to_string(id) + ".png", 1, 320, 240, 100, 1.0});
  WriteFeatureIndex(ws_.string(), index);
  ASSERT_EQ(ReadFeatureIndex(ws_.string()).images.size(), 2u);
  const fs::path json = fs::path(FeaturesDir(ws_.string())) / "images.json";
  const std::string good = ReadBytes(json);
  auto expect_read_error = [&](const std::string& problem) {
    try {
      ReadFeatureIndex(ws_.string());
      ADD_FAILURE() << "accepted, expected " << problem;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(json.string()), std::string::npos) << what;
      EXPECT_NE(what.find(problem), std::string::npos) << what;
    }
  };
  auto expect_error = [&](const std::string& text, const std::string& problem) {
    std::ofstream(json, std::ios::trunc) << text;
    expect_read_error(problem);
  };
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? text : text.replace(at, from.size(), to);
  };
  expect_error(replaced("\"width\": 320", "\"width\": 320, \"width\": 640"), "duplicate key");
  expect_error(replaced("\"width\": 320", "\"width\": 1e999"), "malformed JSON");
  expect_error(replaced("\"image_id\": 2", "\"image_id\": -1"), "image_id: -1 is out of range");
  expect_error(replaced("\"image_id\": 2", "\"image_id\": 1"), "image_id 1 listed twice");
  expect_error(replaced("\"name\": \"im2.png\"", "\"name\": \"im1.png\""), "image im1.png listed twice");
  expect_error(replaced("\"height\": 240", "\"height\": 0"), "height: 0 is out of range");
  expect_error(replaced("\"num_features\": 100", "\"num_features\": 1.5"), "expected an integer");
  expect_error(replaced("\"camera_id\": 1", "\"camera_id\": 7"), "unknown camera 7");
  fs::remove(json);
  ASSERT_EQ(::mkfifo(json.c_str(), 0600), 0);
  expect_read_error("is not a regular file");
}

}  // namespace
}  // namespace pgba
