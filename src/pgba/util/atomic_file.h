// Atomic outputs: nothing half-written is ever left under a final name.
//
// Files are written to "<path>.tmp.<pid>.<n>" and renamed over <path> (rename(2) is atomic
// on one file system). Directories of several files (a COLMAP model) are written into
// "<dir>.tmp.<pid>.<n>/" and swapped in as a whole by StagedDirectory::Commit.
// A path that cannot be written (parent is a file, no permission, path is a directory) or a
// write that fails (a full disk, a file size limit) is an InputError "PATH: cannot ...: cause"
// naming it: the user chose that output path, and the run ends with exit code 2.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

namespace pgba {

// Writes `path` atomically: `writer` fills the stream; on exception or stream failure the
// temporary is removed, the previous content of `path` (if any) is left untouched, and the
// exception propagates (the writer's own, or InputError for an unwritable path or a failed
// write, with the system's reason: "No space left on device").
void WriteFileAtomically(const std::filesystem::path& path,
                         const std::function<void(std::ostream&)>& writer);

// Convenience for a string payload.
void WriteStringAtomically(const std::filesystem::path& path, const std::string& content);

// Checks, before the work whose result goes to `path`, that WriteFileAtomically could write
// it: the same InputError as the write would give (a FIFO or device refused, a parent that is
// a file, no permission), now instead of after the computation. Creates the parent folder;
// leaves `path` itself as it is.
void CheckOutputFile(const std::filesystem::path& path);

// Removes, anywhere below `dir`, the temporaries of this file's writers ("<name>.tmp.<pid>.<n>",
// ".old.", ".probe.", and the ".pgba_write_probe.<pid>" of an output folder's probe) whose
// process is gone: a run killed with SIGKILL leaves them, and the next run over the same
// output clears them. Those of a live process (a concurrent run) are left alone. Returns
// the number removed; errors are ignored (a staging that cannot be removed is harmless).
size_t RemoveStaleStaging(const std::filesystem::path& dir);

// A staging directory that becomes `final_dir` only when Commit() is called. If the object
// is destroyed without Commit() (an exception), the staging directory is removed and
// `final_dir` keeps its previous content. InputError if `final_dir` is an existing file or
// cannot be created.
class StagedDirectory {
 public:
  explicit StagedDirectory(std::filesystem::path final_dir);
  ~StagedDirectory();
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;

  const std::filesystem::path& path() const { return staging_; }
  // Replaces any existing `final_dir` by the staging directory.
  void Commit();

 private:
  std::filesystem::path final_;
  std::filesystem::path staging_;
  bool committed_ = false;
};

}  // namespace pgba
