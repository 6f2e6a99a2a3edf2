// Ground control point file (text, one record per line, '#' comments and blank lines skipped):
//
//   GCP <name> <X> <Y> <Z> [<sigma>]       given coordinates in the GCP frame (metres), and
//                                          optionally their accuracy (1-sigma, metres, > 0)
//   OBS <gcp_name> <image_name> <x> <y>    an observation of that GCP, pixels (COLMAP
//                                          convention: the centre of the top-left pixel is 0.5)
//
// Records may come in any order (an OBS may precede its GCP). Names contain no whitespace.
// Malformed input (unknown keyword, wrong number of fields, a non-finite number, a duplicate
// GCP name, a non-positive sigma, an OBS naming no GCP of the file, a file without any GCP)
// is an InputError "FILE:LINE: problem". Image names are resolved later, against the
// reconstruction (modules/gcp/gcp_constraint.h), where unknown images are warned about and skipped.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace pgba {

struct GcpFileObservation {
  std::string image_name;
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();
  int line = 0;  // for messages
};

struct GcpFileEntry {
  std::string name;
  Eigen::Vector3d X = Eigen::Vector3d::Zero();
  double sigma = 0.0;  // metres; 0 when the file gives none (the caller's default applies)
  std::vector<GcpFileObservation> observations;
  int line = 0;
};

// GCPs in file order, each with its observations in file order.
std::vector<GcpFileEntry> ReadGcpFile(const std::string& path);

// Writes the same format (17 significant digits), atomically.
void WriteGcpFile(const std::vector<GcpFileEntry>& gcps, const std::string& path);

}  // namespace pgba
