#include "modules/gcp/gcp_constraint.h"

#include <set>

#include "pgba/io/option_ranges.h"
#include "pgba/geometry/triangulation.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"

namespace pgba {

std::vector<GcpConstraint> MakeGcpConstraints(const std::vector<GcpFileEntry>& entries, const Reconstruction& rec,
                                              const GcpOptions& options, const std::string& path) {
  std::vector<GcpConstraint> out;
  for (const GcpFileEntry& e : entries) {
    GcpConstraint g;
    g.name = e.name;
    g.X = e.X;
    g.sigma = e.sigma > 0 ? e.sigma : options.default_sigma;
    std::set<uint32_t> seen;
    for (const GcpFileObservation& o : e.observations) {
      const std::optional<uint32_t> id = rec.FindImageByName(o.image_name);
      if (!id) {
        PGBA_LOG_WARN << FormatInputError(path, o.line, "image '" + o.image_name + "' is not in the tracks; skipped");
        continue;
      }
      if (!seen.insert(*id).second) {
        PGBA_LOG_WARN << FormatInputError(path, o.line,
                                          "GCP '" + e.name + "' observed twice in '" + o.image_name + "'; kept the first");
        continue;
      }
      g.observations.push_back({*id, rec.CameraOf(rec.images.at(*id)), o.xy});
    }
    if (g.observations.size() < 2) {
      PGBA_LOG_WARN << FormatInputError(path, e.line, "GCP '" + e.name + "' has " +
                                                          std::to_string(g.observations.size()) +
                                                          " usable observations (< 2); skipped");
      continue;
    }
    out.push_back(std::move(g));
  }
  return out;
}

GcpInput LoadGcps(const std::string& path, const Reconstruction& rec, const GcpOptions& options) {
  if (!(options.default_sigma > 0)) throw InputError("gcp.default_sigma must be > 0 (metres)");
  GcpInput in;
  in.options = options;
  in.path = path;
  in.gcps = MakeGcpConstraints(ReadGcpFile(path), rec, options, path);
  PGBA_LOG_INFO << path << ": " << in.gcps.size() << " usable GCPs";
  return in;
}

std::optional<Eigen::Vector3d> TriangulateGcp(const GcpConstraint& gcp, const std::map<uint32_t, Pose>& poses,
                                              const GcpOptions& options) {
  std::vector<TrackView> views;
  for (const GcpObservation& o : gcp.observations) {
    const auto it = poses.find(o.image_id);
    if (it != poses.end()) views.push_back({it->second, &o.camera, o.pixel});
  }
  if (views.size() < 2) return std::nullopt;
  TriangulationOptions to;
  to.min_angle_deg = options.min_angle_deg;
  const TriangulatedPoint p = TriangulateTrack(views, to);
  if (!p.ok) return std::nullopt;
  return p.X;
}

std::string GcpOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "gcp"); !m.empty()) return m;
  return "";
}

}  // namespace pgba
