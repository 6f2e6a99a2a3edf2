// A fresh temporary folder per test (removed afterwards) and a one-call text file writer,
// for the dataset converter tests.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace pgba::testing {

class TempDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("pgba_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name() + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // Writes `content` to dir_/rel (creating folders); returns the path.
  std::string Write(const std::string& rel, const std::string& content) {
    const std::filesystem::path p = dir_ / rel;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p) << content;
    return p.string();
  }
  static std::string Read(const std::filesystem::path& p) {
    std::ifstream in(p);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  std::filesystem::path dir_;
};

// The smallest JPEG header the converters read a photo's size from (SOI, a baseline SOF0
// frame header of width x height, EOI), followed by `tail`.
inline std::string JpegPhoto(int width, int height, const std::string& tail = "") {
  std::string b("\xFF\xD8\xFF\xC0\x00\x0B\x08", 7);
  for (int v : {height, width}) b += {static_cast<char>((v >> 8) & 0xff), static_cast<char>(v & 0xff)};
  b += std::string("\x01\x01\x11\x00\xFF\xD9", 6);
  return b + tail;
}

}  // namespace pgba::testing
