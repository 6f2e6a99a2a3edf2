// The image catalog with a JSON calibration (pgba/io/calibration_json.h): several cameras
// mapped to images by the file's own "images", the same result as cameras.txt plus a
// camera map; an image missing from the map has no camera.
#include "features/image_catalog.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace pgba {
namespace {
namespace fs = std::filesystem;

TEST(ImageCatalogJson, CamerasAndMapFromTheJsonFileMatchTextFiles) {
  const fs::path root = fs::temp_directory_path() / ("pgba_catalog_json_" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "images");
  for (const char* f : {"a.png", "b.png", "c.png"}) std::ofstream(root / "images" / f) << "x";
  std::ofstream(root / "calib.json") << R"({"cameras": [
      {"camera_id": 1, "model": "PINHOLE", "width": 640, "height": 480, "params": [500, 501, 320, 240]},
      {"camera_id": 2, "model": "SIMPLE_PINHOLE", "width": 320, "height": 240, "params": [250, 160, 120]}],
    "images": {"a.png": 1, "b.png": 2}})";
  std::ofstream(root / "cameras.txt") << "1 PINHOLE 640 480 500 501 320 240\n2 SIMPLE_PINHOLE 320 240 250 160 120\n";
  std::ofstream(root / "map.txt") << "a.png 1\nb.png 2\n";

  const ImageCatalog json = BuildImageCatalog((root / "images").string(), {(root / "calib.json").string(), ""});
  const ImageCatalog text =
      BuildImageCatalog((root / "images").string(), {(root / "cameras.txt").string(), (root / "map.txt").string()});
  EXPECT_EQ(json.calibration_source, "file: " + fs::weakly_canonical(root / "calib.json").string());
  EXPECT_EQ(json.camera_of, text.camera_of);
  EXPECT_FALSE(json.camera_of.count("c.png"));
  ASSERT_EQ(json.cameras.size(), text.cameras.size());
  for (const auto& [id, cam] : text.cameras) EXPECT_EQ(json.cameras.at(id).params, cam.params);
  fs::remove_all(root);
}

// A cameras.txt found beside the images that is a FIFO is an error naming it (skipping it
// would run on priors instead of the user's calibration).
TEST(ImageCatalog, FoundCalibrationThatIsNoRegularFileIsRefused) {
  const fs::path root = fs::temp_directory_path() / ("pgba_catalog_fifo_" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "images");
  for (const char* f : {"a.png", "b.png", "c.png"}) std::ofstream(root / "images" / f) << "x";
  ASSERT_EQ(::mkfifo((root / "images" / "cameras.txt").c_str(), 0600), 0);
  try {
    BuildImageCatalog((root / "images").string(), {"", ""});
    ADD_FAILURE() << "a FIFO cameras.txt was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("cameras.txt"), std::string::npos) << e.what();
  }
  fs::remove_all(root);
}

}  // namespace
}  // namespace pgba
