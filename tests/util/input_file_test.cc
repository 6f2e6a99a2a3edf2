// Every input file goes through RequireRegularFile: a FIFO (which would block the open
// forever), a directory or a missing path is a one-line InputError naming the path.
#include "pgba/util/input_file.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <string>
#include <utility>
#include <vector>

#include "pgba/io/colmap_text.h"
#include "pgba/io/json_config.h"
#include "pgba/io/json_file_reader.h"
#include "pgba/util/error.h"
#include "pgba/util/text_reader.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

class InputFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("pgba_input_file_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The message of `read` on a FIFO at `fifo`. If the reader blocks in open() (the bug),
  // a writer end opened after a few seconds releases it and the test fails instead of hanging.
  std::string ErrorOnFifo(const fs::path& fifo, const std::function<void()>& read) {
    EXPECT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    auto result = std::async(std::launch::async, [&]() -> std::string {
      try {
        read();
      } catch (const InputError& e) {
        return e.what();
      }
      return "accepted";
    });
    if (result.wait_for(std::chrono::seconds(5)) == std::future_status::timeout) {
      const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
      if (fd >= 0) ::close(fd);
      result.wait();
      fs::remove(fifo);
      return "blocked on the FIFO";
    }
    fs::remove(fifo);
    return result.get();
  }
  fs::path dir_;
};

TEST_F(InputFileTest, FifoIsRefusedByEveryReader) {
  const std::string refused = "is not a regular file";
  const fs::path fifo = dir_ / "fifo.txt";
  for (const auto& [name, read] : std::vector<std::pair<std::string, std::function<void()>>>{
           {"TextReader", [&] { TextReader r(fifo.string()); }},
           {"ReadRegularFile", [&] { ReadRegularFile(fifo.string()); }},
           {"Config::Load", [&] { Config::Load(fifo.string()); }},
           {"JsonFileReader", [&] { JsonFileReader(fifo.string()).Parse(); }}}) {
    const std::string msg = ErrorOnFifo(fifo, read);
    EXPECT_EQ(msg.rfind(fifo.string() + ": ", 0), 0u) << name << ": " << msg;
    EXPECT_NE(msg.find(refused), std::string::npos) << name << ": " << msg;
  }
}

// The reported case: a FIFO named images.txt beside valid cameras.txt and points3D.txt.
TEST_F(InputFileTest, FifoImagesTxtOfAModelIsRefused) {
  std::ofstream(dir_ / "cameras.txt") << "1 PINHOLE 640 480 500 500 320 240\n";
  std::ofstream(dir_ / "points3D.txt") << "";
  const std::string msg = ErrorOnFifo(dir_ / "images.txt", [&] { ReadColmapText(dir_.string()); });
  EXPECT_EQ(msg.rfind((dir_ / "images.txt").string() + ": is not a regular file", 0), 0u) << msg;
}

TEST_F(InputFileTest, MissingAndDirectoryAndSymlink) {
  auto error_of = [](const fs::path& p) {
    try {
      ReadRegularFile(p.string());
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(error_of(dir_ / "nope"), (dir_ / "nope").string() + ": file not found");
  EXPECT_EQ(error_of(dir_), dir_.string() + ": is a directory, expected a file");
  std::ofstream(dir_ / "real.txt") << "content";
  fs::create_symlink(dir_ / "real.txt", dir_ / "link.txt");
  EXPECT_EQ(ReadRegularFile((dir_ / "link.txt").string()), "content");  // symlinks are followed
  fs::create_symlink(dir_ / "loop_a", dir_ / "loop_b");
  fs::create_symlink(dir_ / "loop_b", dir_ / "loop_a");
  EXPECT_NE(error_of(dir_ / "loop_a").find("cannot access file"), std::string::npos) << error_of(dir_ / "loop_a");
}

}  // namespace
}  // namespace pgba
