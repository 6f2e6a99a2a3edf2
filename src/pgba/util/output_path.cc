#include "pgba/util/output_path.h"

#include <filesystem>
#include <system_error>

#include "pgba/util/error.h"

namespace pgba {
namespace fs = std::filesystem;

namespace {

// The path with symbolic links and ".." resolved as far as it exists (the rest appended
// as written): two spellings of one folder compare equal.
fs::path Resolved(const std::string& path) {
  std::error_code ec;
  fs::path abs = fs::absolute(path, ec);
  if (ec) abs = fs::path(path);
  fs::path resolved = fs::weakly_canonical(abs, ec);
  if (ec) resolved = abs.lexically_normal();
  // "dir/" and "dir" are one folder.
  if (resolved.filename().empty() && resolved.has_parent_path()) resolved = resolved.parent_path();
  return resolved;
}

// The first component of `child` below `parent`; empty unless `child` lies strictly inside.
std::string FirstComponentBelow(const fs::path& child, const fs::path& parent) {
  const fs::path rel = child.lexically_relative(parent);
  if (rel.empty() || rel == "." || *rel.begin() == "..") return "";
  return rel.begin()->string();
}

bool IsInputFolder(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}

std::string Describe(const NamedInput& in) { return "the input " + in.option + " (" + in.path + ")"; }

}  // namespace

void CheckOutputDirApartFromInputs(const std::string& out, const std::vector<std::string>& written,
                                   const std::vector<NamedInput>& inputs) {
  const fs::path o = Resolved(out);
  for (const NamedInput& in : inputs) {
    if (in.path.empty()) continue;
    const fs::path i = Resolved(in.path);
    if (i == o) ThrowInputError(out, 0, "the output folder is " + Describe(in) + "; choose another output folder");
    if (IsInputFolder(i) && !FirstComponentBelow(o, i).empty())
      ThrowInputError(out, 0, "the output folder lies inside " + Describe(in) + "; choose another output folder");
    const std::string first = FirstComponentBelow(i, o);
    if (first.empty()) continue;
    for (const std::string& name : written)
      if (name == first)
        ThrowInputError(out, 0,
                        "the output " + (fs::path(out) / name).string() + " would replace " + Describe(in) +
                            "; choose another output folder");
  }
}

void CheckOutputFileApartFromInputs(const std::string& out, const std::vector<NamedInput>& inputs) {
  const fs::path o = Resolved(out);
  for (const NamedInput& in : inputs) {
    if (in.path.empty()) continue;
    const fs::path i = Resolved(in.path);
    if (i == o) ThrowInputError(out, 0, "the output file is " + Describe(in) + "; choose another output file");
    if (IsInputFolder(i) && !FirstComponentBelow(o, i).empty())
      ThrowInputError(out, 0, "the output file lies inside " + Describe(in) + "; choose another output file");
  }
}

void RequireOutputPath(const std::string& out, const std::string& option) {
  if (out.empty()) ThrowInputError(option, 0, "is empty; give the output path");
}

}  // namespace pgba
