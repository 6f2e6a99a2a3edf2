// Wall-clock timer and resident memory (peak and current), for the per-stage timings and
// memory of report.json.
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

// Peak resident set size since the last ResetPeakRss() (or the start), in MiB (VmHWM of
// /proc/self/status).
double PeakRssMb();

// Resident set size now, in MiB (VmRSS of /proc/self/status).
double CurrentRssMb();

// Resets the peak (VmHWM) to the current resident size, so that the next PeakRssMb()
// measures one stage alone (Linux /proc/self/clear_refs, value 5). The peak before the reset
// is folded into ProcessPeakRssMb() and into every open PeakRssScope first, so resets never
// hide a peak from them. Returns false where the kernel does not support it; PeakRssMb()
// then stays the process-wide peak.
bool ResetPeakRss();

// The process' peak resident set size since its start, in MiB, across resets. Not the
// getrusage maximum, which the reset lowers too.
double ProcessPeakRssMb();

// The peak resident set size from construction to PeakMb() (MiB), nested scopes and resets
// inside included: e.g. one stage's own peak. Construction resets the kernel's peak (the
// enclosing scopes keep theirs).
class PeakRssScope {
 public:
  PeakRssScope();
  ~PeakRssScope();
  PeakRssScope(const PeakRssScope&) = delete;
  PeakRssScope& operator=(const PeakRssScope&) = delete;
  double PeakMb() const;

 private:
  friend bool ResetPeakRss();
  double folded_mb_ = 0.0;
  PeakRssScope* outer_ = nullptr;
};

}  // namespace pgba
