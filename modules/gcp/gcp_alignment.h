// Frame transfer of the initial global solution to the GCP frame (paper, "Inclusion of
// ground control points", first step): the GCPs triangulated with the initial poses are
// mapped onto their given coordinates by a least-squares similarity T (Umeyama), and T is
// applied to every initial pose; each triplet's global->local similarity d_s becomes
// d_s T^-1, so that the local frames and the relative motions are unchanged. The global BA
// that follows then starts in the GCP frame and its GCP residuals (global_ba/gcp_residual.h) only
// have to correct what the similarity could not.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "modules/gcp/gcp_constraint.h"
#include "pgba/geometry/sim3.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

struct GcpAlignment {
  Sim3 transform;        // old global frame -> GCP frame
  int num_gcps_used = 0;  // GCPs triangulated with the initial poses (outliers dropped)
  double rms_before = 0.0;  // RMS of |P - T(p)| over the used GCPs, after the transfer (metres)
  std::vector<std::string> dropped;  // outlying GCPs, removed from the input (see below)
};

// A GCP is an outlier when, with the similarity fitted to the others, its residual exceeds
// kGcpOutlierFactor x the larger of its sigma and the others' median residual (the initial
// poses' own error): a mistyped coordinate (1000 m off) or a mis-identified target, which
// would drag the whole solution (the check rms then reads hundreds of metres).
constexpr double kGcpOutlierFactor = 20.0;

// The fewest GCPs among which a wrong one can be told apart (see AlignToGcps).
constexpr int kMinGcpsToTellAnOutlier = 5;

// Applies the transfer to `poses` and `triplets` in place. With 5 or more triangulated GCPs,
// outliers (above) are dropped one at a time, worst first, while 4 remain: each is named in
// a warning with the file, removed from `input` (the global BA does not use it) and listed
// in GcpAlignment::dropped. A similarity fitted to 3 GCPs has only 2 redundant equations: its
// residuals do not measure the initial poses' own error, and a correct GCP would read as an
// outlier (one 2.8 m from where 3 others put it, on an aerial block). With 3 or 4 GCPs the
// final check (CheckGcps) says that they disagree. InputError naming the file if fewer than 3
// GCPs can be triangulated with the poses or they are (nearly) collinear.
GcpAlignment AlignToGcps(GcpInput& input, std::map<uint32_t, Pose>* poses, std::vector<LocalMotion>* triplets);

// Check of a solution against the GCPs: each GCP triangulated with `poses` vs its given
// coordinates. A GCP whose error exceeds kGcpOutlierFactor x its sigma is listed in
// "beyond_sigma" of the JSON and named in a warning with the file; with fewer than
// kMinGcpsToTellAnOutlier GCPs, one warning says instead that they disagree and that the wrong
// one cannot be told apart (the frame was fitted to all of them, so the GCPs beyond their
// sigma need not include the wrong one).
struct GcpCheck {
  int num_gcps = 0;  // triangulated
  double rms = 0.0;  // metres
  double max = 0.0;
  std::vector<std::pair<std::string, double>> errors;  // per triangulated GCP
  std::vector<std::string> beyond_sigma;               // error > kGcpOutlierFactor x sigma
  nlohmann::json ToJson() const;
};
GcpCheck CheckGcps(const GcpInput& input, const std::map<uint32_t, Pose>& poses);

}  // namespace pgba
