// Runs the pgba binary (PGBA_BINARY, a compile definition of every test executable) the way
// a user does, for the CLI tests: exit code and everything it printed.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace pgba::test {

struct CliResult {
  int code = -1;
  std::string output;  // stdout + stderr
};

// A shell command's exit code and output (stdout; the command redirects stderr into it).
inline CliResult RunCommand(const std::string& command) {
  CliResult r;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  while (fgets(buf.data(), buf.size(), pipe)) r.output += buf.data();
  const int status = ::pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

inline CliResult RunPgba(const std::string& args) { return RunCommand(std::string(PGBA_BINARY) + " " + args + " 2>&1"); }

// RunPgba under `timeout`: a run still going after `seconds` is killed and reported as
// code 124 (a hang), a run ended by a signal as 128 + the signal.
inline CliResult RunPgbaWithin(int seconds, const std::string& args) {
  return RunCommand("timeout --kill-after=5 " + std::to_string(seconds) + " " + std::string(PGBA_BINARY) + " " +
                    args + " 2>&1");
}

// The same with stdout and stderr apart (tests that check where a message goes).
struct CliStreams {
  int code = -1;
  std::string out, err;
};

inline CliStreams RunPgbaStreams(const std::string& args) {
  char out_path[] = "/tmp/pgba_cli_out_XXXXXX";
  char err_path[] = "/tmp/pgba_cli_err_XXXXXX";
  const int out_fd = ::mkstemp(out_path), err_fd = ::mkstemp(err_path);
  CliStreams r;
  if (out_fd >= 0 && err_fd >= 0) {
    const int status = std::system((std::string(PGBA_BINARY) + " " + args + " > " + out_path + " 2> " + err_path).c_str());
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    auto slurp = [](const char* path) {
      std::string text;
      if (FILE* f = std::fopen(path, "rb")) {
        std::array<char, 4096> buf;
        size_t n;
        while ((n = std::fread(buf.data(), 1, buf.size(), f)) > 0) text.append(buf.data(), n);
        std::fclose(f);
      }
      return text;
    };
    r.out = slurp(out_path);
    r.err = slurp(err_path);
  }
  for (int fd : {out_fd, err_fd})
    if (fd >= 0) ::close(fd);
  std::remove(out_path);
  std::remove(err_path);
  return r;
}

}  // namespace pgba::test
