#include "pgba/util/logging.h"

#include <atomic>
#include <fstream>
#include <iostream>
#include <mutex>

namespace pgba {
namespace {
std::atomic<int> g_verbosity{1};
std::mutex g_mutex;
std::ofstream g_file;
}  // namespace

void SetLogVerbosity(int verbosity) { g_verbosity = verbosity; }
int LogVerbosity() { return g_verbosity; }

void SetLogFile(const std::string& path) {
  std::lock_guard<std::mutex> lock(g_mutex);
  if (g_file.is_open()) g_file.close();
  if (!path.empty()) g_file.open(path, std::ios::app);
}

void LogMessage(LogLevel level, const std::string& text) {
  std::lock_guard<std::mutex> lock(g_mutex);
  if (g_file.is_open()) g_file << text << '\n' << std::flush;
  if (static_cast<int>(level) <= g_verbosity) std::cerr << text << '\n';
}

}  // namespace pgba
