#include "mapper/convergence_curve.h"

#include <limits>
#include <stdexcept>

#include "pgba/io/option_ranges.h"
#include "evaluation/sigma.h"

namespace pgba {

std::string ConvergenceOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "convergence"); !m.empty()) return m;
  return "";
}

nlohmann::json ConvergenceCurve::ToJson() const {
  return {{"iterations", sigma.size()},
          {"tracks_evaluated", tracks_evaluated},
          {"tracks_total", tracks_total},
          {"sampled", Sampled()}};
}

Reconstruction ConvergenceSample(const Reconstruction& tracks, const ConvergenceOptions& options) {
  const size_t n = tracks.points3D.size();
  const size_t m = static_cast<size_t>(options.max_tracks);
  if (m == 0 || n <= m) return tracks;
  Reconstruction sample;
  sample.cameras = tracks.cameras;
  sample.images = tracks.images;
  // Evenly spaced in id order: track ids follow the order the tracks were built in (pairs,
  // then images), so the sample spreads over the whole block.
  size_t position = 0, next = 0, k = 0;
  for (const auto& [id, point] : tracks.points3D) {
    if (position++ != next) continue;
    sample.points3D.emplace(id, point);
    next = static_cast<size_t>((static_cast<unsigned __int128>(++k) * n) / m);
  }
  return sample;
}

ConvergenceCurve EvaluateConvergence(const Reconstruction& tracks, const std::vector<std::map<uint32_t, Pose>>& history,
                                     const ConvergenceOptions& options) {
  const std::string problem = options.Check();
  if (!problem.empty()) throw std::invalid_argument("ConvergenceOptions: " + problem);
  const Reconstruction sample = ConvergenceSample(tracks, options);
  ConvergenceCurve curve;
  curve.tracks_total = tracks.points3D.size();
  curve.tracks_evaluated = sample.points3D.size();
  for (const auto& poses : history) {
    const SigmaResult s = EvaluateSigma(sample, poses);
    curve.sigma.push_back(s.Computable() ? s.rms : std::numeric_limits<double>::quiet_NaN());
  }
  return curve;
}

}  // namespace pgba
