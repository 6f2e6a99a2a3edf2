#include "matching/front_end_geometries.h"

#include <cmath>
#include <filesystem>
#include <set>
#include <utility>

#include "pgba/io/two_view_geometries.h"
#include "pgba/util/error.h"

namespace pgba {

std::string FrontEndGeometriesPath(const std::string& workspace) {
  return (std::filesystem::path(workspace) / "matching" / "two_view_geometries.txt").string();
}

void CheckFrontEndGeometries(const std::vector<TwoViewGeometry>& geometries, const Reconstruction& tracks,
                             const std::string& origin) {
  std::set<std::pair<uint32_t, uint32_t>> seen;
  for (const TwoViewGeometry& g : geometries) {
    const std::string pair = "pair (" + std::to_string(g.image_id1) + ", " + std::to_string(g.image_id2) + "): ";
    for (uint32_t id : {g.image_id1, g.image_id2})
      if (!tracks.images.count(id))
        ThrowInputError(origin, 0, pair + "image " + std::to_string(id) + " is not in the tracks (a stale file?)");
    if (g.image_id1 == g.image_id2) ThrowInputError(origin, 0, pair + "an image paired with itself");
    if (!seen.insert(std::minmax(g.image_id1, g.image_id2)).second)
      ThrowInputError(origin, 0, pair + "listed twice");
    const double orthogonality = (g.R_21.transpose() * g.R_21 - Eigen::Matrix3d::Identity()).norm();
    if (!g.R_21.allFinite() || !(orthogonality < 1e-6) || !(g.R_21.determinant() > 0))
      ThrowInputError(origin, 0, pair + "the rotation is not a rotation");
    if (!g.t_21.allFinite() || !(std::abs(g.t_21.norm() - 1.0) < 1e-6))
      ThrowInputError(origin, 0, pair + "the translation is not a unit vector");
    if (g.num_inliers < 0 || g.num_tracks < 0 || !(g.median_triangulation_angle_deg >= 0))
      ThrowInputError(origin, 0, pair + "negative inlier or track count or triangulation angle");
  }
}

std::vector<TwoViewGeometry> ReadFrontEndGeometries(const std::string& path, const Reconstruction& tracks) {
  std::vector<TwoViewGeometry> geometries = ReadTwoViewGeometries(path);
  CheckFrontEndGeometries(geometries, tracks, path);
  return geometries;
}

}  // namespace pgba
