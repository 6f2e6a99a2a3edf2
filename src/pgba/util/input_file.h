// Opening an input file the user named: it must be a regular file (a symlink to one is
// followed). A FIFO, a socket or a device is refused up front, because opening a FIFO for
// reading blocks until some writer appears: a FIFO named images.txt hung the run forever.
#pragma once

#include <string>

namespace pgba {

// InputError "PATH: file not found" / "is a directory, expected a file" / "is not a regular
// file (FIFO, socket or device)" / "cannot access file: ...".
void RequireRegularFile(const std::string& path);

// The whole content of a regular file (RequireRegularFile, then InputError on a read error).
std::string ReadRegularFile(const std::string& path);

}  // namespace pgba
