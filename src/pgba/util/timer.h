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

// Resets the peak (VmHWM) to the current resident size, so that the next PeakRssMb()
// measures one stage alone (Linux /proc/self/clear_refs, value 5). Returns false where the
// kernel does not support it; PeakRssMb() then stays the process-wide peak.
bool ResetPeakRss();

}  // namespace pgba
