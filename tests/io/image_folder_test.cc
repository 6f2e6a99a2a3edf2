// The image folder as the catalog lists it: a truncated JPEG (libjpeg would only print
// "Premature end of JPEG file", naming no file, and decode grey rows) and an entry that
// cannot be stat'ed (a symlink loop, which aborted the run with a raw filesystem error)
// are each left out with a warning naming the file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "features/image_catalog.h"
#include "pgba/util/error.h"
#include "pgba/util/input_file.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

class ImageFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("pgba_image_folder_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_ / "images");
    cv::Mat img(48, 64, CV_8UC3);
    cv::randu(img, 0, 255);
    for (const char* name : {"a.jpg", "b.jpg", "c.jpg"}) ASSERT_TRUE(cv::imwrite((root_ / "images" / name).string(), img));
    std::ofstream(root_ / "cameras.txt") << "1 PINHOLE 64 48 50 50 32 24\n";
  }
  void TearDown() override { fs::remove_all(root_); }
  ImageCatalog Catalog(std::string* warnings) {
    ::testing::internal::CaptureStderr();
    try {
      ImageCatalog catalog = BuildImageCatalog((root_ / "images").string(), {(root_ / "cameras.txt").string(), ""});
      *warnings = ::testing::internal::GetCapturedStderr();
      return catalog;
    } catch (...) {
      *warnings = ::testing::internal::GetCapturedStderr();
      throw;
    }
  }
  fs::path root_;
};

TEST_F(ImageFolderTest, TruncatedJpegIsSkippedWithAWarningNamingIt) {
  const fs::path b = root_ / "images" / "b.jpg";
  fs::resize_file(b, fs::file_size(b) * 2 / 3);
  std::string warnings;
  const ImageCatalog catalog = Catalog(&warnings);
  EXPECT_EQ(catalog.files, (std::vector<std::string>{"a.jpg", "c.jpg"}));
  EXPECT_NE(warnings.find(fs::weakly_canonical(b).string() + ": truncated JPEG"), std::string::npos) << warnings;
}

TEST_F(ImageFolderTest, CompleteJpegsAndOtherFilesAreKept) {
  std::ofstream(root_ / "images" / "notes.txt") << "not an image";  // the features stage reports it
  std::string warnings;
  const ImageCatalog catalog = Catalog(&warnings);
  EXPECT_EQ(catalog.files, (std::vector<std::string>{"a.jpg", "b.jpg", "c.jpg", "notes.txt"}));
  EXPECT_EQ(warnings.find("truncated"), std::string::npos) << warnings;
}

TEST_F(ImageFolderTest, SymlinkLoopIsSkippedWithAWarningNamingIt) {
  fs::create_symlink(root_ / "images" / "loop1.jpg", root_ / "images" / "loop2.jpg");
  fs::create_symlink(root_ / "images" / "loop2.jpg", root_ / "images" / "loop1.jpg");
  std::string warnings;
  ImageCatalog catalog;
  ASSERT_NO_THROW(catalog = Catalog(&warnings));
  EXPECT_EQ(catalog.files, (std::vector<std::string>{"a.jpg", "b.jpg", "c.jpg"}));
  EXPECT_NE(warnings.find("loop1.jpg: cannot access ("), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("loop2.jpg: cannot access ("), std::string::npos) << warnings;
}

TEST_F(ImageFolderTest, FolderOfOnlyTruncatedJpegsIsAnInputError) {
  for (const char* name : {"a.jpg", "b.jpg", "c.jpg"}) fs::resize_file(root_ / "images" / name, 300);
  std::string warnings;
  EXPECT_THROW(Catalog(&warnings), InputError);
}

}  // namespace
}  // namespace pgba
