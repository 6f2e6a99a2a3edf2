// The checks shared by the readers and the converters (io/input_checks.h, io/image_header.h):
// a camera's focal and principal point, image names that a COLMAP text model keeps, and a
// photo's size read from its PNG or JPEG header.
#include "pgba/io/input_checks.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "pgba/io/colmap_text.h"
#include "pgba/io/image_header.h"
#include "pgba/util/error.h"
#include "tests/io/dataset_test_dir.h"

namespace pgba {
namespace {

Camera Pinhole(double f, double cx, double cy) {
  Camera c;
  c.camera_id = 1;
  c.model = CameraModel::kPinhole;
  c.width = 640;
  c.height = 480;
  c.params = {f, f, cx, cy};
  return c;
}

TEST(InputChecks, CameraFocalAndPrincipalPoint) {
  EXPECT_EQ(CheckCamera(Pinhole(500, 320, 240)), "");
  EXPECT_EQ(CheckCamera(Pinhole(500, 0, 480)), "");  // on the border
  EXPECT_NE(CheckCamera(Pinhole(0, 320, 240)).find("focal length must be positive"), std::string::npos);
  EXPECT_NE(CheckCamera(Pinhole(1e-9, 320, 240)).find("is implausible for a 640x480 image"), std::string::npos);
  EXPECT_NE(CheckCamera(Pinhole(1e300, 320, 240)).find("is implausible"), std::string::npos);
  EXPECT_EQ(CheckCamera(Pinhole(500, 900, 240)), "principal point (900, 240) is outside the 640x480 image");
  EXPECT_NE(CheckCamera(Pinhole(500, 320, -1)).find("outside"), std::string::npos);
}

TEST(InputChecks, ImageNamesMustRoundTripThroughATextModel) {
  EXPECT_EQ(CheckImageName("a b.jpg"), "");
  EXPECT_EQ(CheckImageName("dir/DSC 01.JPG"), "");
  EXPECT_EQ(CheckImageName(""), "empty image name");
  EXPECT_NE(CheckImageName("new\nline.png").find("'new\\x0aline.png' holds a line break"), std::string::npos);
  EXPECT_NE(CheckImageName("cr\r.png").find("line break"), std::string::npos);
  EXPECT_NE(CheckImageName(std::string("nul\0.png", 8)).find("NUL"), std::string::npos);
  EXPECT_NE(CheckImageName("trailing .png ").find("whitespace"), std::string::npos);
  EXPECT_NE(CheckImageName(" leading.png").find("whitespace"), std::string::npos);
  EXPECT_NE(CheckImageName("tab.png\t").find("whitespace"), std::string::npos);
}

class ImageHeaderTest : public testing::TempDirTest {};

TEST_F(ImageHeaderTest, SizesOfPngAndJpegAndCorruptHeaders) {
  EXPECT_EQ(ReadImageSize(Write("a.jpg", testing::JpegPhoto(6048, 4032, "tail"))), std::make_pair(6048, 4032));
  // An APP segment before the frame header is skipped.
  std::string jpeg = testing::JpegPhoto(10, 20);
  jpeg.insert(2, std::string("\xFF\xE1\x00\x04\x00\x00", 6));
  EXPECT_EQ(ReadImageSize(Write("app.jpg", jpeg)), std::make_pair(10, 20));
  std::string png = std::string("\x89PNG\r\n\x1a\n", 8) + std::string("\0\0\0\x0dIHDR", 8) +
                    std::string("\x80\0\0\0\0\0\x01\xe0", 8) + std::string(5, '\0');
  EXPECT_THROW(ReadImageSize(Write("negative.png", png)), InputError);  // width 2^31
  png[16] = 0;
  png[18] = 2;
  png[19] = static_cast<char>(0x80);
  EXPECT_EQ(ReadImageSize(Write("ok.png", png)), std::make_pair(640, 480));
  EXPECT_THROW(ReadImageSize(Write("short.png", png.substr(0, 12))), InputError);
  EXPECT_THROW(ReadImageSize(Write("cut.jpg", testing::JpegPhoto(10, 20).substr(0, 6))), InputError);
  try {
    ReadImageSize(Write("text.jpg", "not a photo"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (dir_ / "text.jpg").string() + ": not a PNG or JPEG photo");
  }
}

// The text model writer refuses a name it would not give back (a line break wrote a broken
// images.txt; a trailing space came back without it), naming the output before writing it.
TEST_F(ImageHeaderTest, TextModelWriterRefusesNamesItCannotKeep) {
  Reconstruction rec;
  rec.cameras[1] = Pinhole(500, 320, 240);
  Image im;
  im.image_id = 1;
  im.camera_id = 1;
  im.name = "trailing .png ";
  rec.images[1] = im;
  const std::string out = (dir_ / "model").string();
  try {
    WriteColmapText(rec, out);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(out + ": image 1: image name 'trailing .png '", 0), 0u) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(out));
  rec.images[1].name = "a b.png";
  WriteColmapText(rec, out);
  EXPECT_EQ(ReadColmapText(out, true).images.at(1).name, "a b.png");
}

}  // namespace
}  // namespace pgba
