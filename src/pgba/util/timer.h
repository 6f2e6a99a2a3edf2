// Wall-clock timer and peak resident memory, for the per-stage timings in report.json.
#pragma once

#include <chrono>

namespace pgba {

class Timer {
 public:
  Timer() : start_(std::chrono::steady_clock::now()) {}
  void Restart() { start_ = std::chrono::steady_clock::now(); }
  double Seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

// Peak resident set size of this process so far, in MiB (VmHWM of /proc/self/status).
double PeakRssMb();

}  // namespace pgba
