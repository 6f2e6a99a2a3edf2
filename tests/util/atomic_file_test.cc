// Atomic outputs: the final name holds either the complete old or the complete new content,
// never a partial file, and no temporary is left behind, whatever the writer does.
#include "pgba/util/atomic_file.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "pgba/util/error.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

class AtomicFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("pgba_atomic_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static std::string Read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  // Every entry under the test directory (recursively), as relative paths.
  std::vector<std::string> Entries() const {
    std::vector<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(dir_)) out.push_back(fs::relative(e.path(), dir_).string());
    std::sort(out.begin(), out.end());
    return out;
  }
  fs::path dir_;
};

using Names = std::vector<std::string>;

TEST_F(AtomicFileTest, WritesAndReplacesWithoutTemporaries) {
  const fs::path f = dir_ / "out.txt";
  WriteStringAtomically(f, "first\n");
  EXPECT_EQ(Read(f), "first\n");
  WriteStringAtomically(f, "second, longer content\n");
  EXPECT_EQ(Read(f), "second, longer content\n");
  WriteStringAtomically(f, "");
  EXPECT_EQ(Read(f), "");
  EXPECT_EQ(Entries(), Names({"out.txt"}));
  // Missing parent directories are created.
  WriteFileAtomically(dir_ / "a" / "b" / "c.txt", [](std::ostream& out) { out << 42; });
  EXPECT_EQ(Read(dir_ / "a" / "b" / "c.txt"), "42");
  EXPECT_EQ(Entries(), Names({"a", "a/b", "a/b/c.txt", "out.txt"}));
}

TEST_F(AtomicFileTest, WriterThrowingKeepsOldContent) {
  const fs::path f = dir_ / "model.txt";
  WriteStringAtomically(f, "old complete content\n");
  struct WriterFailure : std::exception {};
  EXPECT_THROW(WriteFileAtomically(f,
                                   [](std::ostream& out) {
                                     out << "half of the new cont";
                                     out.flush();
                                     throw WriterFailure();
                                   }),
               WriterFailure);  // the writer's own exception, unchanged
  EXPECT_EQ(Read(f), "old complete content\n");
  EXPECT_EQ(Entries(), Names({"model.txt"}));
  // Also when there was no old file: nothing appears.
  EXPECT_THROW(WriteFileAtomically(dir_ / "new.txt", [](std::ostream&) { throw InputError("bad"); }), InputError);
  EXPECT_EQ(Entries(), Names({"model.txt"}));
}

TEST_F(AtomicFileTest, UnwritablePathsAreInputErrors) {
  // The target is a directory.
  fs::create_directory(dir_ / "adir");
  try {
    WriteStringAtomically(dir_ / "adir", "x");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (dir_ / "adir").string() + ": is a directory, cannot write a file there");
  }
  // The parent is a regular file.
  WriteStringAtomically(dir_ / "file", "content");
  try {
    WriteStringAtomically(dir_ / "file" / "child.txt", "x");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind((dir_ / "file" / "child.txt").string() + ": cannot create directory", 0),
              0u)
        << e.what();
  }
  EXPECT_EQ(Read(dir_ / "file"), "content");
  EXPECT_EQ(Entries(), Names({"adir", "file"}));
}

// A write the disk refuses (here a file size limit, which fails write(2) as a full disk does
// with ENOSPC): an InputError naming the file and the system's reason; the old content and
// no temporary are left.
TEST_F(AtomicFileTest, AFailedWriteNamesTheFileAndItsCause) {
  const fs::path f = dir_ / "report.html";
  WriteStringAtomically(f, "old complete content\n");
  rlimit before{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &before), 0);
  const auto previous_handler = std::signal(SIGXFSZ, SIG_IGN);  // write(2) fails with EFBIG instead
  rlimit limited = before;
  limited.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limited), 0);
  std::string message;
  try {
    WriteStringAtomically(f, std::string(100000, 'x'));
  } catch (const InputError& e) {
    message = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &before);
  std::signal(SIGXFSZ, previous_handler);
  EXPECT_EQ(message, f.string() + ": cannot write: File too large");
  EXPECT_EQ(Read(f), "old complete content\n");
  EXPECT_EQ(Entries(), Names({"report.html"}));
}

TEST_F(AtomicFileTest, StagedDirectoryCommitReplacesWholeDirectory) {
  const fs::path model = dir_ / "model";
  fs::create_directories(model);
  WriteStringAtomically(model / "a.txt", "old a");
  WriteStringAtomically(model / "stale.txt", "only in the old model");
  {
    StagedDirectory staged(model);
    EXPECT_NE(staged.path(), model);
    EXPECT_EQ(staged.path().parent_path(), dir_);  // sibling: same file system, rename is atomic
    WriteStringAtomically(staged.path() / "a.txt", "new a");
    WriteStringAtomically(staged.path() / "b.txt", "new b");
    // Nothing visible before the commit.
    EXPECT_EQ(Read(model / "a.txt"), "old a");
    EXPECT_FALSE(fs::exists(model / "b.txt"));
    staged.Commit();
  }
  EXPECT_EQ(Read(model / "a.txt"), "new a");
  EXPECT_EQ(Read(model / "b.txt"), "new b");
  EXPECT_EQ(Entries(), Names({"model", "model/a.txt", "model/b.txt"}));  // stale file gone, no staging left
  // Commit where nothing existed yet (and the parent is missing).
  {
    StagedDirectory staged(dir_ / "deep" / "fresh");
    WriteStringAtomically(staged.path() / "x.txt", "x");
    staged.Commit();
  }
  EXPECT_EQ(Read(dir_ / "deep" / "fresh" / "x.txt"), "x");
}

TEST_F(AtomicFileTest, StagedDirectoryRollbackOnException) {
  const fs::path model = dir_ / "model";
  fs::create_directories(model);
  WriteStringAtomically(model / "a.txt", "old a");
  try {
    StagedDirectory staged(model);
    WriteStringAtomically(staged.path() / "a.txt", "new a");
    throw std::runtime_error("stage failed half-way");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(Read(model / "a.txt"), "old a");
  EXPECT_EQ(Entries(), Names({"model", "model/a.txt"}));
  // Without any previous directory: nothing is created.
  { StagedDirectory staged(dir_ / "never"); }
  EXPECT_EQ(Entries(), Names({"model", "model/a.txt"}));
}

// "out/model/" names the same directory as "out/model": the staging directory must be a
// sibling, not a child of the directory it replaces.
TEST_F(AtomicFileTest, StagedDirectoryWithTrailingSlash) {
  const fs::path model = dir_ / "model";
  fs::create_directories(model);
  WriteStringAtomically(model / "a.txt", "old");
  {
    StagedDirectory staged(model.string() + "/");
    EXPECT_EQ(staged.path().parent_path(), dir_);
    WriteStringAtomically(staged.path() / "a.txt", "new");
    staged.Commit();
  }
  EXPECT_EQ(Read(model / "a.txt"), "new");
  EXPECT_EQ(Entries(), Names({"model", "model/a.txt"}));
}

TEST_F(AtomicFileTest, StagedDirectoryRefusesToReplaceAFile) {
  WriteStringAtomically(dir_ / "model", "a user's file");
  try {
    StagedDirectory staged(dir_ / "model");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (dir_ / "model").string() + ": exists and is not a directory");
  }
  EXPECT_EQ(Read(dir_ / "model"), "a user's file");
  EXPECT_EQ(Entries(), Names({"model"}));
}

// rename(2) over a device node or a FIFO replaces the node by a regular file (as root,
// `--json /dev/full` did): a non-regular output is refused and left as it is.
TEST_F(AtomicFileTest, NonRegularFileIsRefusedNotReplaced) {
  const fs::path fifo = dir_ / "out.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  try {
    WriteStringAtomically(fifo, "{}");
    FAIL() << "replaced the FIFO";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              fifo.string() + ": is not a regular file (device, FIFO or socket), refusing to replace it");
  }
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_EQ(Entries(), Names({"out.json"}));
  if (fs::exists("/dev/full")) {  // the reported case; as root the node itself was at risk
    EXPECT_THROW(WriteStringAtomically("/dev/full", "{}"), InputError);
    EXPECT_TRUE(fs::is_character_file("/dev/full"));
  }
}

// The check made before the work: the write's own InputError for each unwritable path, and
// nothing left behind; a writable path is left as it was (its parent created).
TEST_F(AtomicFileTest, CheckOutputFileGivesTheWritesErrorBeforeTheWork) {
  const fs::path fifo = dir_ / "out.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  fs::create_directory(dir_ / "adir");
  WriteStringAtomically(dir_ / "file", "content");
  for (const fs::path& bad : {fifo, dir_ / "adir", dir_ / "file" / "child.json"}) {
    std::string check_error, write_error;
    try {
      CheckOutputFile(bad);
    } catch (const InputError& e) {
      check_error = e.what();
    }
    try {
      WriteStringAtomically(bad, "{}");
    } catch (const InputError& e) {
      write_error = e.what();
    }
    EXPECT_FALSE(check_error.empty()) << bad << " passed the check";
    EXPECT_EQ(check_error, write_error) << bad;
  }
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_EQ(Entries(), Names({"adir", "file", "out.json"}));
  CheckOutputFile(dir_ / "new" / "metrics.json");
  EXPECT_TRUE(fs::is_directory(dir_ / "new"));
  EXPECT_TRUE(fs::is_empty(dir_ / "new"));
  CheckOutputFile(dir_ / "file");
  EXPECT_EQ(Read(dir_ / "file"), "content");
}

// A symlinked output is written through the link (its target replaced atomically), and the
// link stays a link; a directory symlink likewise for a staged model directory.
TEST_F(AtomicFileTest, SymlinkIsFollowed) {
  fs::create_directories(dir_ / "real");
  WriteStringAtomically(dir_ / "real" / "report.json", "old");
  fs::create_symlink(dir_ / "real" / "report.json", dir_ / "link.json");
  WriteStringAtomically(dir_ / "link.json", "new");
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.json"));
  EXPECT_EQ(Read(dir_ / "real" / "report.json"), "new");
  // A dangling link: its target is created.
  fs::create_symlink(dir_ / "real" / "later.json", dir_ / "dangling.json");
  WriteStringAtomically(dir_ / "dangling.json", "created");
  EXPECT_TRUE(fs::is_symlink(dir_ / "dangling.json"));
  EXPECT_EQ(Read(dir_ / "real" / "later.json"), "created");

  fs::create_directories(dir_ / "models" / "v1");
  WriteStringAtomically(dir_ / "models" / "v1" / "a.txt", "old");
  fs::create_directory_symlink(dir_ / "models" / "v1", dir_ / "sparse");
  {
    StagedDirectory staged(dir_ / "sparse");
    WriteStringAtomically(staged.path() / "a.txt", "new");
    staged.Commit();
  }
  EXPECT_TRUE(fs::is_symlink(dir_ / "sparse"));
  EXPECT_EQ(Read(dir_ / "models" / "v1" / "a.txt"), "new");
  // A link loop is an InputError naming the path.
  fs::create_symlink(dir_ / "loop_a", dir_ / "loop_b");
  fs::create_symlink(dir_ / "loop_b", dir_ / "loop_a");
  EXPECT_THROW(WriteStringAtomically(dir_ / "loop_a", "x"), InputError);
}

}  // namespace
}  // namespace pgba

namespace pgba {
namespace {

// A run killed with SIGKILL left its staging ("<name>.tmp.<pid>.<n>") forever: the next run
// removes the staging of processes that are gone, and leaves a live process' alone.
TEST_F(AtomicFileTest, StaleStagingOfADeadProcessIsRemoved) {
  const std::string dead = "4194305";  // above the largest pid the kernel hands out
  const std::string live = std::to_string(::getppid());
  fs::create_directories(dir_ / ("sparse.tmp." + dead + ".0"));
  std::ofstream(dir_ / ("sparse.tmp." + dead + ".0") / "images.txt") << "partial";
  fs::create_directories(dir_ / "tracks");
  std::ofstream(dir_ / "tracks" / ("key.json.tmp." + dead + ".7")) << "partial";
  std::ofstream(dir_ / ("sparse.old." + dead + ".2")) << "old";
  std::ofstream(dir_ / (".pgba_write_probe." + dead)) << "probe";
  std::ofstream(dir_ / ("report.json.tmp." + live + ".1")) << "a concurrent run";
  std::ofstream(dir_ / "photo.tmp.jpg") << "not staging";
  EXPECT_EQ(RemoveStaleStaging(dir_), 4u);
  EXPECT_EQ(Entries(), (Names{"photo.tmp.jpg", "report.json.tmp." + live + ".1", "tracks"}));
  EXPECT_EQ(RemoveStaleStaging(dir_ / "missing"), 0u);
}

}  // namespace
}  // namespace pgba
