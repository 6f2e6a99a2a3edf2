#include "pgba/util/timer.h"

#include <algorithm>
#include <fstream>
#include <mutex>
#include <string>

namespace pgba {

namespace {

// A "Key:" line of /proc/self/status in kB, as MiB (0 when absent).
double StatusMb(const char* wanted) {
  std::ifstream in("/proc/self/status");
  std::string key;
  while (in >> key) {
    if (key == wanted) {
      double kb = 0;
      in >> kb;
      return kb / 1024.0;
    }
    std::string rest;
    std::getline(in, rest);
  }
  return 0.0;
}

std::mutex& PeakMutex() {
  static std::mutex m;
  return m;
}
double g_folded_process_peak_mb = 0.0;  // the largest peak a reset cleared
PeakRssScope* g_innermost_scope = nullptr;

}  // namespace

double PeakRssMb() { return StatusMb("VmHWM:"); }

double CurrentRssMb() { return StatusMb("VmRSS:"); }

bool ResetPeakRss() {
  const std::lock_guard<std::mutex> lock(PeakMutex());
  const double peak = PeakRssMb();
  g_folded_process_peak_mb = std::max(g_folded_process_peak_mb, peak);
  for (PeakRssScope* s = g_innermost_scope; s; s = s->outer_) s->folded_mb_ = std::max(s->folded_mb_, peak);
  std::ofstream out("/proc/self/clear_refs");
  out << "5";
  out.flush();
  return static_cast<bool>(out);
}

double ProcessPeakRssMb() {
  const std::lock_guard<std::mutex> lock(PeakMutex());
  return std::max(g_folded_process_peak_mb, PeakRssMb());
}

PeakRssScope::PeakRssScope() {
  ResetPeakRss();
  const std::lock_guard<std::mutex> lock(PeakMutex());
  outer_ = g_innermost_scope;
  g_innermost_scope = this;
  folded_mb_ = CurrentRssMb();
}

PeakRssScope::~PeakRssScope() {
  const std::lock_guard<std::mutex> lock(PeakMutex());
  // The enclosing scopes have seen everything up to now through the kernel's peak.
  for (PeakRssScope** s = &g_innermost_scope; *s; s = &(*s)->outer_)
    if (*s == this) {
      *s = outer_;
      break;
    }
}

double PeakRssScope::PeakMb() const {
  const std::lock_guard<std::mutex> lock(PeakMutex());
  return std::max(folded_mb_, PeakRssMb());
}

}  // namespace pgba
