#include "pgba/util/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <regex>

#include <atomic>
#include <fstream>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "pgba/util/error.h"

namespace pgba {
namespace fs = std::filesystem;

namespace {

// "out/model/" and "out/model" name the same directory; the sibling names below must be
// built from the latter, or they would land inside the directory being replaced.
fs::path WithoutTrailingSeparator(const fs::path& path) {
  fs::path p = path.lexically_normal();
  if (p.filename().empty() && p.has_parent_path()) p = p.parent_path();
  return p;
}

// "<path>.<tag>.<pid>.<n>": unique per process and per call, so that threads writing
// different outputs (or a retry) never share a temporary.
fs::path Sibling(const fs::path& path, const char* tag) {
  static std::atomic<unsigned> counter{0};
  return fs::path(path.string() + "." + tag + "." + std::to_string(::getpid()) + "." + std::to_string(counter++));
}

// The path to replace. A symlink is followed (to its final target, which is replaced and
// the link kept), so that an output linked elsewhere is written there; any other
// non-regular file (a device such as /dev/full, a FIFO, a socket) is refused: rename(2)
// would replace the device node itself by a regular file when run as root.
fs::path ResolveOutput(const fs::path& path, bool directory) {
  fs::path target = WithoutTrailingSeparator(path);
  std::error_code ec;
  // Link by link (a dangling link's target is where the file goes; weakly_canonical would
  // stop at the link itself), at most 40 as the kernel does.
  for (int links = 0; fs::is_symlink(fs::symlink_status(target, ec)); ++links) {
    const fs::path next = fs::read_symlink(target, ec);
    if (ec || links == 40)
      ThrowInputError(path.string(), 0,
                      "cannot resolve the symbolic link: " + (ec ? ec.message() : std::string("too many levels")));
    target = next.is_absolute() ? next : target.parent_path() / next;
  }
  const fs::file_status status = fs::status(target, ec);
  if (ec && status.type() != fs::file_type::not_found)
    ThrowInputError(path.string(), 0, "cannot access: " + ec.message());
  const fs::file_type type = status.type();
  if (type == fs::file_type::not_found || type == fs::file_type::none) return target;
  if (directory && type != fs::file_type::directory) ThrowInputError(target.string(), 0, "exists and is not a directory");
  if (!directory && type == fs::file_type::directory)
    ThrowInputError(target.string(), 0, "is a directory, cannot write a file there");
  if (!directory && type != fs::file_type::regular)
    ThrowInputError(target.string(), 0, "is not a regular file (device, FIFO or socket), refusing to replace it");
  return target;
}

void CreateParent(const fs::path& path) {
  if (!path.has_parent_path()) return;
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  if (ec) ThrowInputError(path.string(), 0, "cannot create directory " + path.parent_path().string() + ": " + ec.message());
}

// An output stream buffer over a file descriptor that keeps the errno of the first failed
// write (or close), so that a failed output names its cause: "No space left on device" for a
// full disk, "File too large", "Input/output error". std::ofstream keeps only a failbit.
class FileWriteBuffer : public std::streambuf {
 public:
  explicit FileWriteBuffer(int fd) : fd_(fd) { setp(buffer_, buffer_ + sizeof(buffer_)); }
  ~FileWriteBuffer() override {
    if (fd_ >= 0) ::close(fd_);
  }
  FileWriteBuffer(const FileWriteBuffer&) = delete;
  FileWriteBuffer& operator=(const FileWriteBuffer&) = delete;

  // Writes what is buffered and closes the file; the errno of the first failure, 0 if none.
  int Close() {
    WriteBuffered();
    if (fd_ >= 0 && ::close(fd_) != 0 && error_ == 0) error_ = errno;
    fd_ = -1;
    return error_;
  }

 protected:
  int_type overflow(int_type c) override {
    if (!WriteBuffered()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return WriteBuffered() ? 0 : -1; }

 private:
  bool WriteBuffered() {
    for (const char* p = pbase(); error_ == 0 && p < pptr();) {
      const ssize_t n = ::write(fd_, p, static_cast<size_t>(pptr() - p));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) error_ = n < 0 ? errno : EIO;
      else p += n;
    }
    setp(buffer_, buffer_ + sizeof(buffer_));
    return error_ == 0;
  }

  int fd_;
  int error_ = 0;
  char buffer_[1 << 16];
};

}  // namespace

void WriteFileAtomically(const fs::path& path, const std::function<void(std::ostream&)>& writer) {
  const fs::path target = ResolveOutput(path, /*directory=*/false);
  CreateParent(target);
  std::error_code ec;
  const fs::path tmp = Sibling(target, "tmp");
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) ThrowInputError(target.string(), 0, std::string("cannot open for writing: ") + std::strerror(errno));
  try {
    {
      FileWriteBuffer buffer(fd);
      std::ostream out(&buffer);
      writer(out);
      // A full disk or a file size limit: the file is not written, and the error names it
      // (exit code 2, as for any output path the user's system cannot take).
      if (const int error = buffer.Close(); error != 0)
        ThrowInputError(target.string(), 0, std::string("cannot write: ") + std::strerror(error));
      if (!out) ThrowInputError(target.string(), 0, "cannot write: the output stream failed");
    }
    fs::rename(tmp, target, ec);
    if (ec) ThrowInputError(target.string(), 0, "cannot replace file: " + ec.message());
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
}

void WriteStringAtomically(const fs::path& path, const std::string& content) {
  WriteFileAtomically(path, [&](std::ostream& out) { out << content; });
}

void CheckOutputFile(const fs::path& path) {
  const fs::path target = ResolveOutput(path, /*directory=*/false);
  CreateParent(target);
  const fs::path probe = Sibling(target, "probe");
  {
    std::ofstream out(probe, std::ios::binary | std::ios::trunc);
    if (!out) ThrowInputError(target.string(), 0, "cannot open for writing");
  }
  std::error_code ec;
  fs::remove(probe, ec);
}

size_t RemoveStaleStaging(const fs::path& dir) {
  static const std::regex kStaging(R"(.*\.(tmp|old|probe)\.([0-9]{1,10})\.[0-9]+|\.pgba_write_probe\.([0-9]{1,10}))");
  std::vector<fs::path> stale;
  std::error_code ec;
  fs::recursive_directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    std::smatch m;
    const std::string name = it->path().filename().string();
    if (!std::regex_match(name, m, kStaging)) continue;
    const long long pid = std::stoll(m[2].matched ? m[2].str() : m[3].str());
    // kill(pid, 0) fails with ESRCH only when no such process exists.
    const bool gone = pid != ::getpid() && (pid <= 0 || pid > INT32_MAX ||
                                            (::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH));
    if (!gone) continue;
    stale.push_back(it->path());
    std::error_code ignored;
    if (it->is_directory(ignored)) it.disable_recursion_pending();
  }
  size_t removed = 0;
  for (const fs::path& p : stale) {
    std::error_code ignored;
    if (fs::remove_all(p, ignored) > 0) ++removed;
  }
  return removed;
}

StagedDirectory::StagedDirectory(fs::path final_dir)
    : final_(ResolveOutput(final_dir, /*directory=*/true)), staging_(Sibling(final_, "tmp")) {
  std::error_code ec;
  CreateParent(final_);
  fs::remove_all(staging_, ec);
  fs::create_directories(staging_, ec);
  if (ec) ThrowInputError(final_.string(), 0, "cannot create staging directory " + staging_.string() + ": " + ec.message());
}

StagedDirectory::~StagedDirectory() {
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(staging_, ec);
  }
}

void StagedDirectory::Commit() {
  // A directory cannot be renamed over a non-empty one: move the old one aside first so
  // that at every instant `final_` is either the complete old or the complete new model
  // (or, for the instant between the two renames, absent), and put it back if the second
  // rename fails.
  const fs::path old = Sibling(final_, "old");
  std::error_code ec;
  const bool had_old = fs::exists(final_, ec);
  if (had_old) {
    fs::rename(final_, old, ec);
    if (ec) ThrowInputError(final_.string(), 0, "cannot move the previous output aside: " + ec.message());
  }
  fs::rename(staging_, final_, ec);
  if (ec) {
    std::error_code ignored;
    if (had_old) fs::rename(old, final_, ignored);
    ThrowInputError(final_.string(), 0, "cannot move the new output in place: " + ec.message());
  }
  if (had_old) fs::remove_all(old, ec);
  committed_ = true;
}

}  // namespace pgba
