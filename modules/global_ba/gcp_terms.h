// Which GCP residuals the global BA gets: for every used triplet and every GCP observed in
// at least 2 of its 3 images, the GCP triangulated in the triplet's local frame (from the
// local BA's poses x0), weighted 1 / (number of triplets of that GCP) (gcp/gcp_constraint.h).
#pragma once

#include <vector>

#include "modules/gcp/gcp_constraint.h"
#include "modules/global_ba/gcp_residual.h"
#include "modules/local_hessian/local_hessian.h"

namespace pgba {

// `hessians[i]` is the i-th used triplet term of the global BA (GcpTripletTerm::term = i).
std::vector<GcpTripletTerm> BuildGcpTerms(const GcpInput& input, const std::vector<const LocalHessian*>& hessians);

// True if the terms involve at least 3 distinct GCPs whose given coordinates are not
// (nearly) collinear: the GCPs then fix the 7-dof gauge of the global problem and none of
// the poses or similarities needs to be held.
bool GcpTermsFixGauge(const GcpInput& input, const std::vector<GcpTripletTerm>& terms);

}  // namespace pgba
