#include "pgba/util/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <fstream>
#include <stdexcept>
#include <system_error>

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

void CreateParent(const fs::path& path) {
  if (!path.has_parent_path()) return;
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  if (ec) ThrowInputError(path.string(), 0, "cannot create directory " + path.parent_path().string() + ": " + ec.message());
}

}  // namespace

void WriteFileAtomically(const fs::path& path, const std::function<void(std::ostream&)>& writer) {
  const fs::path target = WithoutTrailingSeparator(path);
  CreateParent(target);
  std::error_code ec;
  if (fs::is_directory(target, ec)) ThrowInputError(target.string(), 0, "is a directory, cannot write a file there");
  const fs::path tmp = Sibling(target, "tmp");
  try {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) ThrowInputError(target.string(), 0, "cannot open for writing");
    writer(out);
    out.flush();
    out.close();
    if (!out) throw std::runtime_error(target.string() + ": write failed (disk full?)");
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

StagedDirectory::StagedDirectory(fs::path final_dir)
    : final_(WithoutTrailingSeparator(final_dir)), staging_(Sibling(final_, "tmp")) {
  std::error_code ec;
  if (fs::exists(final_, ec) && !fs::is_directory(final_, ec))
    ThrowInputError(final_.string(), 0, "exists and is not a directory");
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
