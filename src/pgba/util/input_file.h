// Opening an input file the user named: it must be a regular file (a symlink to one is
// followed). A FIFO, a socket or a device is refused up front, because opening a FIFO for
// reading blocks until some writer appears: a FIFO named images.txt hung the run forever.
#pragma once

#include <string>

namespace pgba {

// InputError "PATH: file not found" / "is a directory, expected a file" / "is not a regular
// file (FIFO, socket or device)" / "cannot access file: ...".
void RequireRegularFile(const std::string& path);

// An input folder the user named: InputError "PATH: WHAT not found" / "cannot access: Too
// many levels of symbolic links" (a link loop, no permission) / "is not a directory
// (expected WHAT_EXPECTED)".
void RequireDirectory(const std::string& path, const std::string& what, const std::string& what_expected);

// The whole content of a regular file (RequireRegularFile, then InputError on a read error).
std::string ReadRegularFile(const std::string& path);

}  // namespace pgba
