#include "pgba/util/atomic_file.h"

#include <unistd.h>

#include <fstream>
#include <stdexcept>
#include <system_error>

namespace pgba {
namespace fs = std::filesystem;

namespace {
fs::path TempSibling(const fs::path& path) {
  return fs::path(path.string() + ".tmp." + std::to_string(::getpid()));
}
}  // namespace

void WriteFileAtomically(const fs::path& path, const std::function<void(std::ostream&)>& writer) {
  if (path.has_parent_path()) fs::create_directories(path.parent_path());
  const fs::path tmp = TempSibling(path);
  try {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path.string() + ": cannot open for writing");
    writer(out);
    out.flush();
    if (!out) throw std::runtime_error(path.string() + ": write failed (disk full?)");
    out.close();
    fs::rename(tmp, path);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

void WriteStringAtomically(const fs::path& path, const std::string& content) {
  WriteFileAtomically(path, [&](std::ostream& out) { out << content; });
}

StagedDirectory::StagedDirectory(fs::path final_dir)
    : final_(std::move(final_dir)), staging_(TempSibling(final_)) {
  std::error_code ec;
  fs::remove_all(staging_, ec);
  fs::create_directories(staging_);
}

StagedDirectory::~StagedDirectory() {
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(staging_, ec);
  }
}

void StagedDirectory::Commit() {
  // A directory cannot be renamed over a non-empty one: move the old one aside first so
  // that at every instant `final_` is either the complete old or the complete new model.
  const fs::path old = fs::path(final_.string() + ".old." + std::to_string(::getpid()));
  std::error_code ec;
  const bool had_old = fs::exists(final_);
  if (had_old) fs::rename(final_, old);
  fs::rename(staging_, final_);
  if (had_old) fs::remove_all(old, ec);
  committed_ = true;
}

}  // namespace pgba
