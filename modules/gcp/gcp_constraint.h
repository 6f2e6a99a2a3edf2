// Ground control points as constraints of the pointless global BA (paper, "Inclusion of
// ground control points"): each GCP has given coordinates P in the GCP frame, an accuracy
// sigma (metres) and pixel observations in images of the reconstruction.
//
// Weighting choice (documented here, used by global_ba/gcp_residual.h): the GCP residual is whitened by
// sigma, r = (P - d_s^-1(p_s)) / sigma, so it is in standard deviations like the triplet
// residuals (whitened for a 1 px observation noise, h in 1/px^2). A GCP seen by n triplets
// gives n residuals that all reuse the same few image observations (strongly correlated
// estimates of one point), so each is weighted 1 / n: every GCP then counts as one 3D
// observation of accuracy sigma, however many triplets see it.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pgba/geometry/pose.h"
#include "pgba/io/gcp_file.h"
#include "pgba/scene/camera.h"
#include "pgba/scene/reconstruction.h"

namespace pgba {

struct GcpOptions {
  // Accuracy (1-sigma, metres) of GCPs whose file line gives none: a surveyed target
  // (GNSS RTK / total station) is typically good to a few centimetres.
  double default_sigma = 0.05;
  // Huber threshold of each GCP residual, in sigmas (<= 0: plain least squares). A
  // mis-identified GCP then pulls linearly, not quadratically.
  double huber_sigmas = 3.0;
  // A GCP is triangulated (in a triplet's local frame, or with the initial poses) only if
  // its rays span at least this angle (degrees); below it its depth is unobservable.
  double min_angle_deg = 1.0;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(GcpOptions, default_sigma, huber_sigmas, min_angle_deg)

struct GcpObservation {
  uint32_t image_id = 0;
  Camera camera;  // a copy: the constraint does not depend on the reconstruction's lifetime
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
};

struct GcpConstraint {
  std::string name;
  Eigen::Vector3d X = Eigen::Vector3d::Zero();  // given coordinates, GCP frame
  double sigma = 0.05;                          // metres
  std::vector<GcpObservation> observations;     // at most one per image
};

// The optional GCP input of the global BA.
struct GcpInput {
  std::vector<GcpConstraint> gcps;
  GcpOptions options;
  std::string path;  // the GCP file, for the messages ("" when not from a file)
};

// Resolves the file's image names against `rec`: observations of unknown images (and
// repeated observations of a GCP in one image, the first kept) are warned about and
// skipped; GCPs left with fewer than 2 observations are warned about and skipped.
// `path` names the file in the messages.
std::vector<GcpConstraint> MakeGcpConstraints(const std::vector<GcpFileEntry>& entries, const Reconstruction& rec,
                                              const GcpOptions& options, const std::string& path);

// ReadGcpFile + MakeGcpConstraints.
GcpInput LoadGcps(const std::string& path, const Reconstruction& rec, const GcpOptions& options);

// Triangulates the GCP from the observations whose image has a pose in `poses` (any frame:
// global initial poses, or a triplet's local poses keyed by image id). nullopt if fewer than
// 2 such observations, a degenerate geometry or rays closer than options.min_angle_deg.
std::optional<Eigen::Vector3d> TriangulateGcp(const GcpConstraint& gcp, const std::map<uint32_t, Pose>& poses,
                                              const GcpOptions& options);

}  // namespace pgba
