#include "pgba/util/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "pgba/util/logging.h"

namespace pgba {

ProgressBar::ProgressBar(std::string label, size_t total)
    : label_(std::move(label)), total_(total), tty_(::isatty(2) && LogVerbosity() >= 1) {}

ProgressBar::~ProgressBar() { Finish(); }

void ProgressBar::Increment(size_t n) {
  const size_t done = done_ += n;
  if (!tty_) return;
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  const double now = timer_.Seconds();
  if (now - last_draw_ < 0.2 && done < total_) return;
  last_draw_ = now;
  Draw(done, false);
}

void ProgressBar::Finish() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (finished_) return;
  finished_ = true;
  Draw(done_, true);
}

void ProgressBar::Draw(size_t done, bool final) {
  const double t = timer_.Seconds();
  // Clamped: more increments than announced (a caller's miscount) must not make the bar
  // longer than its width (std::string of a negative length would throw).
  const double frac = total_ ? std::min(1.0, static_cast<double>(done) / total_) : 1.0;
  const double eta = frac > 0 ? t * (1.0 - frac) / frac : 0.0;
  const int width = 30;
  const int filled = static_cast<int>(frac * width + 0.5);
  char line[256];
  std::snprintf(line, sizeof(line), "%-22s [%s%s] %zu/%zu %5.1fs%s", label_.c_str(),
                std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(), done,
                total_, t, final ? "" : (" ETA " + std::to_string(static_cast<int>(eta)) + "s").c_str());
  // Every stage with a bar prints its own summary line when it ends: the finished bar is
  // erased from a terminal, and a log gets its last state at -v 2 only.
  if (tty_ && final) {
    std::fprintf(stderr, "\r\033[K");
  } else if (tty_) {
    std::fprintf(stderr, "\r%s\033[K", line);
  } else if (final && LogVerbosity() >= 2) {
    std::fprintf(stderr, "%s\n", line);
  }
}

}  // namespace pgba
