// A thread-safe progress bar with ETA on stderr, for stages longer than a few seconds.
// It redraws at most every 0.2 s and only when stderr is a terminal, and is erased when it
// finishes (the stage's own summary line follows); a log that is no terminal gets the bar's
// last state at -v 2 only, instead of thousands of carriage returns.
#pragma once

#include <atomic>
#include <cstddef>
#include <mutex>
#include <string>

#include "pgba/util/timer.h"

namespace pgba {

class ProgressBar {
 public:
  ProgressBar(std::string label, size_t total);
  ~ProgressBar();
  // Thread-safe: may be called from TBB workers.
  void Increment(size_t n = 1);
  void Finish();

 private:
  void Draw(size_t done, bool final);
  std::string label_;
  size_t total_;
  std::atomic<size_t> done_{0};
  std::mutex mutex_;
  Timer timer_;
  double last_draw_ = -1.0;
  bool finished_ = false;
  bool tty_ = false;
};

}  // namespace pgba
