#include "tests/fuzz/fuzz_support.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "pgba/util/error.h"

namespace pgba::fuzz {
namespace fs = std::filesystem;

namespace {
const char* kSeparator = "\n=====\n";

void RemoveScratch() {
  std::error_code ec;
  fs::remove_all(ScratchDir(), ec);
}
}  // namespace

const fs::path& ScratchDir() {
  static const fs::path dir = [] {
    std::error_code ec;
    const fs::path base = fs::is_directory("/dev/shm", ec) ? fs::path("/dev/shm") : fs::temp_directory_path();
    fs::path d = base / ("pgba_fuzz_" + std::to_string(::getpid()));
    fs::create_directories(d);
    std::atexit(RemoveScratch);
    return d;
  }();
  return dir;
}

std::string WriteScratchFile(const std::string& name, const std::string& bytes) {
  const fs::path path = ScratchDir() / name;
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return path.string();
}

void ExpectValueOrInputError(const std::string& path, const std::function<void()>& parse) {
  try {
    parse();
  } catch (const InputError& e) {
    const std::string msg = e.what();
    Require(msg.find('\n') == std::string::npos, "InputError message spans several lines: " + msg);
    Require(msg.rfind(path, 0) == 0, "InputError message does not start with the file " + path + ": " + msg);
  } catch (const std::exception& e) {
    Require(false, std::string("exception other than InputError: ") + e.what());
  }
}

void Require(bool ok, const std::string& what) {
  if (ok) return;
  std::fprintf(stderr, "fuzz: %s\n", what.c_str());
  std::abort();
}

std::vector<std::string> SplitParts(const std::string& bytes, size_t n) {
  std::vector<std::string> parts;
  size_t start = 0;
  while (parts.size() + 1 < n) {
    const size_t sep = bytes.find(kSeparator, start);
    if (sep == std::string::npos) break;
    parts.push_back(bytes.substr(start, sep - start));
    start = sep + std::string(kSeparator).size();
  }
  parts.push_back(bytes.substr(std::min(start, bytes.size())));
  parts.resize(n);
  return parts;
}

std::string JoinParts(const std::vector<std::string>& parts) {
  std::string out;
  for (size_t i = 0; i < parts.size(); ++i) out += (i ? kSeparator : "") + parts[i];
  return out;
}

}  // namespace pgba::fuzz
