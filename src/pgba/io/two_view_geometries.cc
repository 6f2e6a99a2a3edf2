#include "pgba/io/two_view_geometries.h"

#include <Eigen/Geometry>
#include <iomanip>

#include "pgba/util/atomic_file.h"
#include "pgba/util/text_reader.h"

namespace pgba {

void WriteTwoViewGeometries(const std::vector<TwoViewGeometry>& geometries, const std::string& path) {
  WriteFileAtomically(path, [&](std::ostream& out) {
    out << "# Verified two-view geometries: x_2 = R_21 x_1 + t_21, |t_21| = 1\n"
        << "# IMAGE_ID1 IMAGE_ID2 QW QX QY QZ TX TY TZ NUM_INLIERS NUM_TRACKS MEDIAN_TRIANGULATION_ANGLE_DEG\n"
        << "# Number of pairs: " << geometries.size() << "\n"
        << std::setprecision(17);
    for (const TwoViewGeometry& g : geometries) {
      const Eigen::Quaterniond q(g.R_21);
      out << g.image_id1 << ' ' << g.image_id2 << ' ' << q.w() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' '
          << g.t_21.x() << ' ' << g.t_21.y() << ' ' << g.t_21.z() << ' ' << g.num_inliers << ' ' << g.num_tracks << ' '
          << g.median_triangulation_angle_deg << '\n';
    }
  });
}

std::vector<TwoViewGeometry> ReadTwoViewGeometries(const std::string& path) {
  TextReader reader(path);
  std::vector<TwoViewGeometry> out;
  std::vector<std::string> tok;
  while (reader.NextLine(&tok)) {
    reader.RequireTokens(tok, 12, "two-view geometry");
    TwoViewGeometry g;
    g.image_id1 = static_cast<uint32_t>(reader.ToInt(tok[0], "IMAGE_ID1"));
    g.image_id2 = static_cast<uint32_t>(reader.ToInt(tok[1], "IMAGE_ID2"));
    Eigen::Quaterniond q(reader.ToDouble(tok[2], "QW"), reader.ToDouble(tok[3], "QX"), reader.ToDouble(tok[4], "QY"),
                         reader.ToDouble(tok[5], "QZ"));
    if (!(q.norm() > 0.5)) reader.Fail("quaternion is not unit");
    g.R_21 = q.normalized().toRotationMatrix();
    g.t_21 =
        Eigen::Vector3d(reader.ToDouble(tok[6], "TX"), reader.ToDouble(tok[7], "TY"), reader.ToDouble(tok[8], "TZ"));
    g.num_inliers = static_cast<int>(reader.ToInt(tok[9], "NUM_INLIERS"));
    g.num_tracks = static_cast<int>(reader.ToInt(tok[10], "NUM_TRACKS"));
    g.median_triangulation_angle_deg = reader.ToDouble(tok[11], "MEDIAN_TRIANGULATION_ANGLE_DEG");
    out.push_back(g);
  }
  return out;
}

}  // namespace pgba
