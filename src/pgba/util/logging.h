// Minimal leveled logging to stderr (and optionally a log file), thread-safe.
// Verbosity: 0 = warnings/errors only, 1 = info (default), 2 = debug.
#pragma once

#include <sstream>
#include <string>

namespace pgba {

enum class LogLevel { kError = 0, kWarning = 0, kInfo = 1, kDebug = 2 };

void SetLogVerbosity(int verbosity);
int LogVerbosity();
// Also append every message to this file ("" disables). InputError naming it if it cannot
// be written, or is a FIFO, a device or a socket (CheckOutputFile): opening a FIFO blocks.
void SetLogFile(const std::string& path);
void LogMessage(LogLevel level, const std::string& text);

namespace internal {
class LogLine {
 public:
  explicit LogLine(LogLevel level) : level_(level) {}
  ~LogLine() { LogMessage(level_, stream_.str()); }
  template <typename T>
  LogLine& operator<<(const T& v) {
    stream_ << v;
    return *this;
  }

 private:
  LogLevel level_;
  std::ostringstream stream_;
};
}  // namespace internal

}  // namespace pgba

#define PGBA_LOG_INFO ::pgba::internal::LogLine(::pgba::LogLevel::kInfo)
#define PGBA_LOG_DEBUG ::pgba::internal::LogLine(::pgba::LogLevel::kDebug)
#define PGBA_LOG_WARN ::pgba::internal::LogLine(::pgba::LogLevel::kWarning) << "warning: "
