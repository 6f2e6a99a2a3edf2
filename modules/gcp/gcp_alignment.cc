#include "modules/gcp/gcp_alignment.h"

#include <algorithm>
#include <cmath>

#include "pgba/util/error.h"
#include "pgba/util/logging.h"

namespace pgba {

namespace {

std::string Where(const GcpInput& input) { return input.path.empty() ? std::string("GCPs") : input.path; }

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// The GCP (index into src) most beyond kGcpOutlierFactor, each judged with the similarity
// fitted to the others; -1 if none.
int WorstOutlier(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst,
                 const std::vector<double>& sigma, double* residual) {
  int worst = -1;
  double worst_ratio = 1.0;
  for (size_t i = 0; i < src.size(); ++i) {
    std::vector<Eigen::Vector3d> s, d;
    for (size_t j = 0; j < src.size(); ++j)
      if (j != i) s.push_back(src[j]), d.push_back(dst[j]);
    Sim3 t;
    if (!EstimateSim3(s, d, &t)) continue;
    std::vector<double> others;
    for (size_t j = 0; j < s.size(); ++j) others.push_back((d[j] - t.Apply(s[j])).norm());
    const double r = (dst[i] - t.Apply(src[i])).norm();
    const double ratio = r / (kGcpOutlierFactor * std::max(sigma[i], Median(others)));
    if (ratio > worst_ratio) {
      worst_ratio = ratio;
      worst = static_cast<int>(i);
      *residual = r;
    }
  }
  return worst;
}

}  // namespace

GcpAlignment AlignToGcps(GcpInput& input, std::map<uint32_t, Pose>* poses, std::vector<LocalMotion>* triplets) {
  std::vector<Eigen::Vector3d> src, dst;
  std::vector<double> sigma;
  std::vector<size_t> index;  // into input.gcps
  for (size_t k = 0; k < input.gcps.size(); ++k) {
    const GcpConstraint& g = input.gcps[k];
    const std::optional<Eigen::Vector3d> p = TriangulateGcp(g, *poses, input.options);
    if (!p) {
      PGBA_LOG_WARN << Where(input) << ": GCP '" << g.name
                    << "' cannot be triangulated with the initial poses; not used for the frame";
      continue;
    }
    src.push_back(*p);
    dst.push_back(g.X);
    sigma.push_back(g.sigma);
    index.push_back(k);
  }
  GcpAlignment a;
  std::vector<bool> drop(input.gcps.size(), false);
  while (static_cast<int>(src.size()) >= kMinGcpsToTellAnOutlier) {
    double residual = 0.0;
    const int worst = WorstOutlier(src, dst, sigma, &residual);
    if (worst < 0) break;
    const GcpConstraint& g = input.gcps[index[worst]];
    PGBA_LOG_WARN << Where(input) << ": GCP '" << g.name << "' is " << residual
                  << " m from where the other GCPs put it (sigma " << g.sigma
                  << " m): dropped as an outlier (a wrong coordinate or a mis-identified target?)";
    a.dropped.push_back(g.name);
    drop[index[worst]] = true;
    src.erase(src.begin() + worst);
    dst.erase(dst.begin() + worst);
    sigma.erase(sigma.begin() + worst);
    index.erase(index.begin() + worst);
  }
  a.num_gcps_used = static_cast<int>(src.size());
  if (src.size() < 3 || !EstimateSim3(src, dst, &a.transform))
    ThrowInputError(Where(input), 0,
                    std::to_string(src.size()) +
                        " GCPs triangulated with the initial poses; at least 3 non-collinear ones are needed to move "
                        "the solution into the GCP frame");
  if (!a.dropped.empty()) {
    std::vector<GcpConstraint> kept;
    for (size_t k = 0; k < input.gcps.size(); ++k)
      if (!drop[k]) kept.push_back(std::move(input.gcps[k]));
    input.gcps = std::move(kept);
  }
  double sum = 0.0;
  for (size_t i = 0; i < src.size(); ++i) sum += (dst[i] - a.transform.Apply(src[i])).squaredNorm();
  a.rms_before = std::sqrt(sum / src.size());
  for (auto& [id, pose] : *poses) pose = a.transform.Apply(pose);
  const Sim3 inverse = a.transform.Inverse();
  for (LocalMotion& t : *triplets) t.global_to_local = t.global_to_local * inverse;
  PGBA_LOG_INFO << "GCP frame transfer: " << a.num_gcps_used << " GCPs, scale " << a.transform.s << ", RMS "
                << a.rms_before << " m after the similarity";
  return a;
}

GcpCheck CheckGcps(const GcpInput& input, const std::map<uint32_t, Pose>& poses) {
  GcpCheck c;
  double sum = 0.0;
  for (const GcpConstraint& g : input.gcps) {
    const std::optional<Eigen::Vector3d> p = TriangulateGcp(g, poses, input.options);
    if (!p) continue;
    const double e = (*p - g.X).norm();
    c.errors.emplace_back(g.name, e);
    sum += e * e;
    c.max = std::max(c.max, e);
    if (e > kGcpOutlierFactor * g.sigma) c.beyond_sigma.push_back(g.name);
  }
  c.num_gcps = static_cast<int>(c.errors.size());
  if (!c.beyond_sigma.empty() && c.num_gcps < kMinGcpsToTellAnOutlier) {
    // The frame was fitted to all of them: a wrong one pulls the others off as well, and the
    // GCPs beyond their sigma need not include it.
    PGBA_LOG_WARN << Where(input) << ": the " << c.num_gcps << " GCPs disagree with the result by up to " << c.max
                  << " m, more than " << kGcpOutlierFactor << " x their sigma; with fewer than "
                  << kMinGcpsToTellAnOutlier
                  << " GCPs the wrong one cannot be told apart: check every GCP's coordinates and observations";
  } else {
    for (const auto& [name, e] : c.errors) {
      const auto it = std::find(c.beyond_sigma.begin(), c.beyond_sigma.end(), name);
      if (it == c.beyond_sigma.end()) continue;
      PGBA_LOG_WARN << Where(input) << ": GCP '" << name << "' is " << e << " m from its coordinates with the final "
                    << "poses, more than " << kGcpOutlierFactor << " x its sigma: check its coordinates and "
                    << "observations";
    }
  }
  c.rms = c.num_gcps ? std::sqrt(sum / c.num_gcps) : 0.0;
  return c;
}

nlohmann::json GcpCheck::ToJson() const {
  nlohmann::json j = {{"gcps", num_gcps}, {"rms_m", rms}, {"max_m", max}};
  j["errors_m"] = nlohmann::json::object();
  j["beyond_sigma"] = beyond_sigma;
  for (const auto& [name, e] : errors) j["errors_m"][name] = e;
  return j;
}

}  // namespace pgba
