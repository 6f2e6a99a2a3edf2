#include "modules/global_ba/gcp_terms.h"

#include <Eigen/SVD>
#include <map>
#include <set>

namespace pgba {

std::vector<GcpTripletTerm> BuildGcpTerms(const GcpInput& input, const std::vector<const LocalHessian*>& hessians) {
  std::vector<GcpTripletTerm> terms;
  std::vector<int> count(input.gcps.size(), 0);
  for (size_t s = 0; s < hessians.size(); ++s) {
    std::map<uint32_t, Pose> local;
    for (int k = 0; k < hessians[s]->num_views(); ++k) local[hessians[s]->image_ids[k]] = hessians[s]->local_poses[k];
    for (size_t g = 0; g < input.gcps.size(); ++g) {
      const std::optional<Eigen::Vector3d> p = TriangulateGcp(input.gcps[g], local, input.options);
      if (!p) continue;
      GcpTripletTerm t;
      t.term = s;
      t.gcp = static_cast<int>(g);
      t.P = input.gcps[g].X;
      t.p_local = *p;
      t.sigma = input.gcps[g].sigma;
      terms.push_back(t);
      ++count[g];
    }
  }
  for (GcpTripletTerm& t : terms) t.weight = 1.0 / count[t.gcp];
  return terms;
}

bool GcpTermsFixGauge(const GcpInput& input, const std::vector<GcpTripletTerm>& terms) {
  std::set<int> used;
  for (const GcpTripletTerm& t : terms) used.insert(t.gcp);
  if (used.size() < 3) return false;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int g : used) mean += input.gcps[g].X;
  mean /= used.size();
  Eigen::MatrixXd A(used.size(), 3);
  int row = 0;
  for (int g : used) A.row(row++) = (input.gcps[g].X - mean).transpose();
  const Eigen::Vector3d sv = Eigen::JacobiSVD<Eigen::MatrixXd>(A).singularValues();
  // Collinear: the second singular value vanishes against the first.
  return sv(0) > 0 && sv(1) > 1e-3 * sv(0);
}

}  // namespace pgba
