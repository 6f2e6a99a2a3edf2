#include "pgba/util/logging.h"

#include <atomic>
#include <fstream>
#include <iostream>
#include <mutex>

#include "pgba/util/atomic_file.h"
#include "pgba/util/error.h"

namespace pgba {
namespace {
std::atomic<int> g_verbosity{1};
std::mutex g_mutex;
std::ofstream g_file;
}  // namespace

void SetLogVerbosity(int verbosity) { g_verbosity = verbosity; }
int LogVerbosity() { return g_verbosity; }

void SetLogFile(const std::string& path) {
  // Before the lock (it logs nothing): opening a FIFO for writing blocks until a reader comes.
  if (!path.empty()) CheckOutputFile(path);
  std::lock_guard<std::mutex> lock(g_mutex);
  if (g_file.is_open()) g_file.close();
  if (path.empty()) return;
  g_file.open(path, std::ios::app);
  if (!g_file) ThrowInputError(path, 0, "cannot open the log for writing");
}

void LogMessage(LogLevel level, const std::string& text) {
  std::lock_guard<std::mutex> lock(g_mutex);
  if (g_file.is_open()) g_file << text << '\n' << std::flush;
  if (static_cast<int>(level) <= g_verbosity) std::cerr << text << '\n';
}

}  // namespace pgba
