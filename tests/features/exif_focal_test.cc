// Focal priors for folders without a calibration file (exif_focal.h, image_catalog.h): the
// EXIF focal of real photos against their independent calibration, the default for a PNG,
// crafted EXIF blocks (both rules; corrupt ones fall back without crashing), and catalogs
// built from EXIF instead of failing.
#include "features/exif_focal.h"

#include <gtest/gtest.h>
#include <libexif/exif-data.h>
#include <libexif/exif-utils.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <opencv2/imgcodecs.hpp>

#include "features/image_catalog.h"
#include "pgba/io/colmap_text.h"
#include "pgba/util/error.h"
#include "tests/support/shared_data.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

const fs::path kSceaux = fs::path(PGBA_SHARED_DIR) / "datasets" / "sceaux_castle";

std::vector<fs::path> SceauxImages() {
  std::vector<fs::path> images;
  if (fs::is_directory(kSceaux / "images"))
    for (const auto& e : fs::directory_iterator(kSceaux / "images")) images.push_back(e.path());
  std::sort(images.begin(), images.end());
  return images;
}

// Writes a JPEG of a flat w x h image whose first segment after SOI is an APP1 with `app1`.
void WriteJpegWithApp1(const fs::path& path, int w, int h, const std::string& app1) {
  std::vector<uchar> jpg;
  cv::imencode(".jpg", cv::Mat(h, w, CV_8U, cv::Scalar(128)), jpg);
  const size_t len = app1.size() + 2;
  std::string out(jpg.begin(), jpg.begin() + 2);
  out += "\xFF\xE1";
  out += static_cast<char>(len >> 8);
  out += static_cast<char>(len & 0xFF);
  out += app1;
  out.append(jpg.begin() + 2, jpg.end());
  std::ofstream(path, std::ios::binary) << out;
}

// An EXIF block ("Exif\0\0" + TIFF) written by libexif with the given tags in the EXIF IFD.
struct Tag {
  ExifTag tag;
  ExifFormat format;
  double value;
};
std::string ExifBlock(const std::vector<Tag>& tags) {
  ExifData* data = exif_data_new();
  exif_data_unset_option(data, EXIF_DATA_OPTION_FOLLOW_SPECIFICATION);
  exif_data_set_byte_order(data, EXIF_BYTE_ORDER_INTEL);
  for (const Tag& t : tags) {
    ExifEntry* e = exif_entry_new();
    e->tag = t.tag;
    e->format = t.format;
    e->components = 1;
    e->size = exif_format_get_size(t.format);
    e->data = static_cast<unsigned char*>(std::calloc(1, e->size));
    if (t.format == EXIF_FORMAT_SHORT) {
      exif_set_short(e->data, EXIF_BYTE_ORDER_INTEL, static_cast<ExifShort>(t.value));
    } else {
      exif_set_rational(e->data, EXIF_BYTE_ORDER_INTEL, {static_cast<ExifLong>(t.value * 1000), 1000});
    }
    exif_content_add_entry(data->ifd[EXIF_IFD_EXIF], e);
    exif_entry_unref(e);
  }
  unsigned char* buf = nullptr;
  unsigned int size = 0;
  exif_data_save_data(data, &buf, &size);
  std::string block(reinterpret_cast<const char*>(buf), size);
  std::free(buf);
  exif_data_unref(data);
  return block;
}

class ExifFocalTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("pgba_exif_" + std::to_string(::getpid()) + "_" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_ / "images");  // neither it nor root_ holds a cameras.txt
  }
  void TearDown() override { fs::remove_all(root_); }
  fs::path root_;
};

TEST(ExifFocal, SceauxFocalAgreesWithItsCalibration) {
  const std::vector<fs::path> images = SceauxImages();
  PGBA_NEED_SHARED_DATA(!images.empty(), kSceaux.string());
  const std::map<uint32_t, Camera> cameras = ReadColmapCameras((kSceaux / "cameras.txt").string());
  ASSERT_EQ(cameras.size(), 1u);
  const Camera& truth = cameras.begin()->second;
  for (const fs::path& image : images) {
    const FocalPrior prior = ExifFocalPrior(image.string(), truth.width, truth.height);
    std::cout << image.filename().string() << ": EXIF focal " << prior.focal_px << " px ("
              << FocalSourceName(prior.source) << "), cameras.txt focal " << truth.params[0] << " px, ratio "
              << prior.focal_px / truth.params[0] << std::endl;
    EXPECT_EQ(prior.source, FocalSource::kExif35mm) << image;
    EXPECT_TRUE(prior.problem.empty()) << prior.problem;
    EXPECT_NEAR(prior.focal_px / truth.params[0], 1.0, 0.03) << image;
  }
}

TEST_F(ExifFocalTest, PngWithoutExifGetsTheDefault) {
  const fs::path png = root_ / "images" / "a.png";
  cv::imwrite(png.string(), cv::Mat(240, 320, CV_8U, cv::Scalar(50)));
  const FocalPrior prior = ExifFocalPrior(png.string(), 320, 240);
  EXPECT_EQ(prior.source, FocalSource::kDefault);
  EXPECT_DOUBLE_EQ(prior.focal_px, 1.2 * 320);
  EXPECT_TRUE(prior.problem.empty()) << prior.problem;  // no EXIF is normal, not a problem
  // A file that does not exist, or is not an image, gets the default too.
  EXPECT_EQ(ExifFocalPrior((root_ / "missing.jpg").string(), 100, 200).focal_px, 240.0);
}

TEST_F(ExifFocalTest, BothExifRules) {
  // 35 mm equivalent, 3:2: the CIPA diagonal rule equals f35 / 36 * max(w, h).
  const fs::path a = root_ / "images" / "f35.jpg";
  WriteJpegWithApp1(a, 300, 200, ExifBlock({{EXIF_TAG_FOCAL_LENGTH_IN_35MM_FILM, EXIF_FORMAT_SHORT, 50}}));
  const FocalPrior pa = ExifFocalPrior(a.string(), 300, 200);
  EXPECT_EQ(pa.source, FocalSource::kExif35mm);
  EXPECT_NEAR(pa.focal_px, 50.0 / 36.0 * 300, 0.5);
  // FocalLength 4.5 mm with 2000 pixels per cm on the focal plane: 4.5 * 200 px.
  const fs::path b = root_ / "images" / "plane.jpg";
  WriteJpegWithApp1(b, 300, 200,
                    ExifBlock({{EXIF_TAG_FOCAL_LENGTH, EXIF_FORMAT_RATIONAL, 4.5},
                               {EXIF_TAG_FOCAL_PLANE_X_RESOLUTION, EXIF_FORMAT_RATIONAL, 2000},
                               {EXIF_TAG_FOCAL_PLANE_RESOLUTION_UNIT, EXIF_FORMAT_SHORT, 3}}));
  const FocalPrior pb = ExifFocalPrior(b.string(), 300, 200);
  EXPECT_EQ(pb.source, FocalSource::kExifFocalPlane);
  EXPECT_NEAR(pb.focal_px, 900.0, 1e-6);
  // FocalLength alone (COLMAP would consult its sensor database; pgba has none): default.
  const fs::path c = root_ / "images" / "mm_only.jpg";
  WriteJpegWithApp1(c, 300, 200, ExifBlock({{EXIF_TAG_FOCAL_LENGTH, EXIF_FORMAT_RATIONAL, 4.5}}));
  EXPECT_EQ(ExifFocalPrior(c.string(), 300, 200).source, FocalSource::kDefault);
  // An absurd value (65535 mm equivalent) is a broken tag: default, with the reason.
  const fs::path d = root_ / "images" / "absurd.jpg";
  WriteJpegWithApp1(d, 300, 200, ExifBlock({{EXIF_TAG_FOCAL_LENGTH_IN_35MM_FILM, EXIF_FORMAT_SHORT, 65535}}));
  const FocalPrior pd = ExifFocalPrior(d.string(), 300, 200);
  EXPECT_EQ(pd.source, FocalSource::kDefault);
  EXPECT_NE(pd.problem.find("implausible"), std::string::npos) << pd.problem;
}

TEST_F(ExifFocalTest, CorruptExifFallsBackWithoutCrashing) {
  const std::string good = ExifBlock({{EXIF_TAG_FOCAL_LENGTH_IN_35MM_FILM, EXIF_FORMAT_SHORT, 28}});
  std::string garbage = "Exif";
  garbage += std::string("\0\0", 2);
  cv::RNG rng(3);
  for (int i = 0; i < 300; ++i) garbage += static_cast<char>(rng.uniform(0, 256));
  std::string huge_ifd = "Exif";
  huge_ifd += std::string("\0\0II*\0\x08\0\0\0\xFF\xFF", 12);  // 65535 entries, none present
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"garbage", garbage}, {"huge_ifd", huge_ifd}, {"truncated", good.substr(0, good.size() / 2)}, {"header", "Exif"}};
  for (const auto& [name, block] : cases) {
    const fs::path path = root_ / "images" / (name + ".jpg");
    WriteJpegWithApp1(path, 300, 200, block);
    const FocalPrior p = ExifFocalPrior(path.string(), 300, 200);
    EXPECT_EQ(p.source, FocalSource::kDefault) << name;
    EXPECT_DOUBLE_EQ(p.focal_px, 360.0) << name;
    std::cout << name << ": " << (p.problem.empty() ? "(no problem reported)" : p.problem) << std::endl;
  }
  // The catalog still takes the images (OpenCV skips the APP1 segment) and warns.
  const ImageCatalog catalog = BuildImageCatalog((root_ / "images").string(), {});
  ASSERT_EQ(catalog.cameras.size(), 1u);
  EXPECT_EQ(catalog.camera_of.size(), cases.size());
  EXPECT_EQ(catalog.calibration_source, "default-prior");
}

TEST_F(ExifFocalTest, CatalogWithoutCalibrationUsesExif) {
  const std::vector<fs::path> images = SceauxImages();
  PGBA_NEED_SHARED_DATA(!images.empty(), kSceaux.string());
  for (size_t i = 0; i < 3; ++i) fs::create_symlink(images[i], root_ / "images" / images[i].filename());
  const ImageCatalog catalog = BuildImageCatalog((root_ / "images").string(), {});
  EXPECT_EQ(catalog.calibration_source, "exif");
  EXPECT_EQ(catalog.cameras_path, "");
  ASSERT_EQ(catalog.cameras.size(), 1u);
  const Camera& cam = catalog.cameras.at(1);
  EXPECT_EQ(cam.model, CameraModel::kSimpleRadial);  // COLMAP's default without a calibration
  EXPECT_EQ(cam.width, 2832);
  EXPECT_EQ(cam.height, 2128);
  EXPECT_EQ(cam.params[1], 1416.0);
  EXPECT_EQ(cam.params[2], 1064.0);
  EXPECT_EQ(cam.params[3], 0.0);  // k
  EXPECT_EQ(cam.params[0], ExifFocalPrior(images[0].string(), 2832, 2128).focal_px);
  EXPECT_TRUE(cam.has_prior_focal_length);  // EXIF is a prior: not estimated by default
  EXPECT_EQ(catalog.camera_of.size(), 3u);
  EXPECT_EQ(cam.Validate(), "");

  // The report's source (the features stage passes the catalog's on): a cameras.txt found
  // next to the images takes over from EXIF.
  std::ofstream(root_ / "cameras.txt") << "1 PINHOLE 2832 2128 2905.88 2905.88 1416 1064\n";
  const ImageCatalog with_file = BuildImageCatalog((root_ / "images").string(), {});
  EXPECT_EQ(with_file.calibration_source, "file: " + (root_ / "cameras.txt").string());
  EXPECT_EQ(with_file.cameras.at(1).params[0], 2905.88);
}

TEST_F(ExifFocalTest, CatalogGroupsPriorsBySizeAndFocal) {
  cv::imwrite((root_ / "images" / "a.png").string(), cv::Mat(240, 320, CV_8U, cv::Scalar(50)));
  cv::imwrite((root_ / "images" / "b.png").string(), cv::Mat(300, 400, CV_8U, cv::Scalar(50)));
  cv::imwrite((root_ / "images" / "c.png").string(), cv::Mat(240, 320, CV_8U, cv::Scalar(90)));
  WriteJpegWithApp1(root_ / "images" / "d.jpg", 320, 240,
                    ExifBlock({{EXIF_TAG_FOCAL_LENGTH_IN_35MM_FILM, EXIF_FORMAT_SHORT, 35}}));
  std::ofstream(root_ / "images" / "notes.txt") << "not an image\n";
  const ImageCatalog catalog = BuildImageCatalog((root_ / "images").string(), {});
  ASSERT_EQ(catalog.cameras.size(), 3u);
  EXPECT_EQ(catalog.camera_of.at("a.png"), 1u);
  EXPECT_EQ(catalog.camera_of.at("b.png"), 2u);
  EXPECT_EQ(catalog.camera_of.at("c.png"), 1u);
  EXPECT_EQ(catalog.camera_of.at("d.jpg"), 3u);
  EXPECT_EQ(catalog.camera_of.at("notes.txt"), 1u);  // so the features stage says "not an image"
  EXPECT_DOUBLE_EQ(catalog.cameras.at(1).params[0], 384.0);
  EXPECT_DOUBLE_EQ(catalog.cameras.at(2).params[0], 480.0);
  EXPECT_NEAR(catalog.cameras.at(3).params[0], 35.0 / 43.27 * 400.0, 1e-9);
  EXPECT_EQ(catalog.calibration_source, "exif+default-prior");
  // Only the 1.2 * max(w, h) guesses lack a prior focal (the view graph estimates theirs).
  EXPECT_FALSE(catalog.cameras.at(1).has_prior_focal_length);
  EXPECT_FALSE(catalog.cameras.at(2).has_prior_focal_length);
  EXPECT_TRUE(catalog.cameras.at(3).has_prior_focal_length);
  for (const auto& [id, cam] : catalog.cameras) EXPECT_EQ(cam.model, CameraModel::kSimpleRadial) << id;
}

TEST_F(ExifFocalTest, FatalInputsWithoutCalibration) {
  std::ofstream(root_ / "images" / "notes.txt") << "not an image\n";
  try {
    BuildImageCatalog((root_ / "images").string(), {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--calib"), std::string::npos) << e.what();
  }
  cv::imwrite((root_ / "images" / "a.png").string(), cv::Mat(240, 320, CV_8U, cv::Scalar(50)));
  std::ofstream(root_ / "map.txt") << "a.png 1\n";
  EXPECT_THROW(BuildImageCatalog((root_ / "images").string(), {"", (root_ / "map.txt").string()}), InputError);
}

}  // namespace
}  // namespace pgba
