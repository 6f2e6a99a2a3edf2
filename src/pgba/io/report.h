// report.json of `init` / `reconstruct` / `run` (docs/formats.md, "Reports"):
//   {"stages": {NAME: {"seconds": s, "cpu_seconds": c, "load_average": l, "peak_rss_mb": m,
//                      "rss_mb": r, "order": k, ...stage extras}},
//    "peak_rss_mb": p, "images_registered": n, "images_dropped": [names], ...}
// A thin layer over nlohmann::json: stages record their wall time, the process' CPU time
// over the stage (user + system of every thread: on a shared machine the wall time grows
// with the others' load, the CPU time hardly), the 1-minute load average at its end, the
// stage's own peak resident memory (MiB, util/timer.h PeakRssScope) and the resident memory
// it leaves behind; the top-level "peak_rss_mb" is the process' peak so far. Everything else
// is free-form. Written atomically, so a crashed run never leaves
// a truncated report behind.
#pragma once

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "pgba/util/cpu_time.h"
#include "pgba/util/timer.h"

namespace pgba {

// A finite number as itself, NaN or inf as null (JSON has neither): the reports' spelling of
// "not measured".
inline nlohmann::json NumberOrNull(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

class Report {
 public:
  Report() : root_(nlohmann::json::object()) {}

  // Top-level free-form keys: report["images_registered"] = 42.
  nlohmann::json& operator[](const std::string& key) { return root_[key]; }
  const nlohmann::json& json() const { return root_; }

  // Records stage `name` (replacing an earlier record of the same name) with its seconds,
  // its peak resident memory (`peak_rss_mb` < 0: the kernel's peak since its last reset), the
  // resident memory now and its position in the run ("order", since JSON objects are
  // unordered); returns the stage object for extra fields. Updates the process' peak.
  // `cpu_seconds` < 0: not measured (no key).
  nlohmann::json& AddStage(const std::string& name, double seconds, double cpu_seconds = -1.0,
                           double peak_rss_mb = -1.0);

  // Pretty-printed, atomically (InputError/runtime_error if the path is not writable).
  void Write(const std::string& path) const;

 private:
  nlohmann::json root_;
};

// Times a stage from construction to Stop() (or destruction) and records it in the report.
//   { StageTimer t(&report, "triplets"); ...; t.Stop()["num_triplets"] = n; }
class StageTimer {
 public:
  StageTimer(Report* report, std::string name) : report_(report), name_(std::move(name)) {}
  ~StageTimer() {
    if (!stopped_) Stop();
  }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;
  nlohmann::json& Stop();

 private:
  Report* report_;
  std::string name_;
  Timer timer_;
  CpuTimer cpu_timer_;
  PeakRssScope memory_;
  bool stopped_ = false;
};

}  // namespace pgba
