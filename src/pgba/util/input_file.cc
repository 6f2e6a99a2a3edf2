#include "pgba/util/input_file.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "pgba/util/error.h"

namespace pgba {
namespace fs = std::filesystem;

void RequireRegularFile(const std::string& path) {
  // error_code overloads: a path we may not even stat (permissions, a symlink loop) is an
  // input error too, not a filesystem_error escaping to the caller.
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (status.type() == fs::file_type::not_found) ThrowInputError(path, 0, "file not found");
  if (ec) ThrowInputError(path, 0, "cannot access file: " + ec.message());
  if (status.type() == fs::file_type::directory) ThrowInputError(path, 0, "is a directory, expected a file");
  if (status.type() != fs::file_type::regular)
    ThrowInputError(path, 0, "is not a regular file (FIFO, socket or device), refusing to read it");
}

void RequireDirectory(const std::string& path, const std::string& what, const std::string& what_expected) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (status.type() == fs::file_type::not_found) ThrowInputError(path, 0, what + " not found");
  if (ec) ThrowInputError(path, 0, "cannot access: " + ec.message());
  if (status.type() != fs::file_type::directory) ThrowInputError(path, 0, "is not a directory (expected " + what_expected + ")");
}

std::string ReadRegularFile(const std::string& path) {
  RequireRegularFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) ThrowInputError(path, 0, "cannot open file for reading");
  std::stringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) ThrowInputError(path, 0, "read error");
  return buffer.str();
}

}  // namespace pgba
