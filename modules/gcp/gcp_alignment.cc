#include "modules/gcp/gcp_alignment.h"

#include <algorithm>
#include <cmath>

#include "pgba/util/error.h"
#include "pgba/util/logging.h"

namespace pgba {

GcpAlignment AlignToGcps(const GcpInput& input, std::map<uint32_t, Pose>* poses, std::vector<LocalMotion>* triplets) {
  std::vector<Eigen::Vector3d> src, dst;
  for (const GcpConstraint& g : input.gcps) {
    const std::optional<Eigen::Vector3d> p = TriangulateGcp(g, *poses, input.options);
    if (!p) {
      PGBA_LOG_WARN << "GCP '" << g.name << "' cannot be triangulated with the initial poses; not used for the frame";
      continue;
    }
    src.push_back(*p);
    dst.push_back(g.X);
  }
  GcpAlignment a;
  a.num_gcps_used = static_cast<int>(src.size());
  if (src.size() < 3 || !EstimateSim3(src, dst, &a.transform))
    throw InputError("GCPs: " + std::to_string(src.size()) +
                     " GCPs triangulated with the initial poses; at least 3 non-collinear ones are needed to move "
                     "the solution into the GCP frame");
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
  }
  c.num_gcps = static_cast<int>(c.errors.size());
  c.rms = c.num_gcps ? std::sqrt(sum / c.num_gcps) : 0.0;
  return c;
}

nlohmann::json GcpCheck::ToJson() const {
  nlohmann::json j = {{"gcps", num_gcps}, {"rms_m", rms}, {"max_m", max}};
  j["errors_m"] = nlohmann::json::object();
  for (const auto& [name, e] : errors) j["errors_m"][name] = e;
  return j;
}

}  // namespace pgba
