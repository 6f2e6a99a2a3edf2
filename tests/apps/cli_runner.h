// Runs the pgba binary (PGBA_BINARY, a compile definition of every test executable) the way
// a user does, for the CLI tests: exit code and everything it printed.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace pgba::test {

struct CliResult {
  int code = -1;
  std::string output;  // stdout + stderr
};

inline CliResult RunPgba(const std::string& args) {
  CliResult r;
  FILE* pipe = ::popen((std::string(PGBA_BINARY) + " " + args + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  while (fgets(buf.data(), buf.size(), pipe)) r.output += buf.data();
  const int status = ::pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace pgba::test
