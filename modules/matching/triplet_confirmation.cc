#include "matching/triplet_confirmation.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <unordered_map>

#include "pgba/io/option_ranges.h"
#include "pgba/geometry/rotation.h"

namespace pgba {
namespace {

constexpr double kDeg = 180.0 / M_PI;

// d_ik = a d_ij + b d_jk (all in i's frame): (a, b), and the normal of the plane of d_ij
// and d_jk; false when those two are parallel to within 2 degrees.
bool SplitBaseline(const Eigen::Vector3d& d_ij, const Eigen::Vector3d& d_jk, const Eigen::Vector3d& d_ik,
                   Eigen::Vector2d* ab, Eigen::Vector3d* normal) {
  const Eigen::Vector3d n = d_ij.cross(d_jk);
  if (n.norm() <= std::sin(2.0 / kDeg)) return false;
  Eigen::Matrix<double, 3, 2> A;
  A << d_ij, d_jk;
  *ab = A.colPivHouseholderQr().solve(d_ik);
  *normal = n.normalized();
  return true;
}

// Marks kLeafPair, for every image without a kept pair (verified: -2, confirmed: >= 0),
// its unconfirmed weak pair with the most inliers (ties: the first) to an image with one.
void KeepLeafPairs(const std::vector<PairEstimate>& pairs, std::vector<int64_t>* third) {
  std::set<uint32_t> linked;
  for (size_t p = 0; p < pairs.size(); ++p)
    if ((*third)[p] != -1) linked.insert(pairs[p].image1), linked.insert(pairs[p].image2);
  std::map<uint32_t, size_t> best;  // leaf image -> its pair
  for (size_t p = 0; p < pairs.size(); ++p) {
    if ((*third)[p] != -1) continue;
    const uint32_t a = pairs[p].image1, b = pairs[p].image2;
    for (const auto& [leaf, other] : {std::pair(a, b), std::pair(b, a)}) {
      if (linked.count(leaf) || !linked.count(other)) continue;
      const auto it = best.find(leaf);
      if (it == best.end() || pairs[p].matches.size() > pairs[it->second].matches.size()) best[leaf] = p;
    }
  }
  for (const auto& [leaf, p] : best) (*third)[p] = kLeafPair;
}

}  // namespace

std::string TripletConfirmationOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "matching.verification.weak_pairs"); !m.empty()) return m;
  return "";
}

std::unordered_map<uint32_t, uint32_t> PairPartnersFrom(const PairEstimate& p, uint32_t x) {
  std::unordered_map<uint32_t, uint32_t> m;
  m.reserve(p.matches.size());
  for (const auto& [a, b] : p.matches) {
    if (p.image1 == x)
      m.emplace(a, b);
    else
      m.emplace(b, a);
  }
  return m;
}

Eigen::Matrix3d PairRotationFrom(const PairEstimate& p, uint32_t x) {
  return p.image1 == x ? p.R_21 : Eigen::Matrix3d(p.R_21.transpose());
}

Eigen::Vector3d PairCentreDirectionFrom(const PairEstimate& p, uint32_t x) {
  const Eigen::Vector3d c = p.image1 == x ? Eigen::Vector3d(-p.R_21.transpose() * p.t_21) : p.t_21;
  return c.normalized();
}

namespace {

// The triangle's three baselines in i's frame: j's centre along d_ij, k's along d_ik, and k
// from j along d_jk. `closes`: d_ik = a d_ij + b d_jk with a, b > 0 (ab), n the unit normal of
// the plane of d_ij and d_jk.
struct TriangleBaselines {
  Eigen::Matrix3d R_ij;
  Eigen::Vector3d d_ij, d_ik, d_jk, n;
  Eigen::Vector2d ab;
  bool closes = false;
};

TriangleBaselines BaselinesOf(uint32_t i, uint32_t j, const PairEstimate& ij, const PairEstimate& ik,
                              const PairEstimate& jk) {
  TriangleBaselines b;
  b.R_ij = PairRotationFrom(ij, i);
  b.d_ij = PairCentreDirectionFrom(ij, i);
  b.d_ik = PairCentreDirectionFrom(ik, i);
  b.d_jk = b.R_ij.transpose() * PairCentreDirectionFrom(jk, j);
  b.closes = SplitBaseline(b.d_ij, b.d_jk, b.d_ik, &b.ab, &b.n) && b.ab(0) > 0 && b.ab(1) > 0;
  return b;
}

}  // namespace

TriangleTest TestTriangle(uint32_t i, uint32_t j, uint32_t k, const PairEstimate& ij, const PairEstimate& ik,
                          const PairEstimate& jk) {
  TriangleTest t;
  const TriangleBaselines b = BaselinesOf(i, j, ij, ik, jk);
  const Eigen::Matrix3d R_jk = PairRotationFrom(jk, j), R_ki = PairRotationFrom(ik, k);
  t.rotation_cycle_deg = RotationAngleDeg(R_ki * R_jk * b.R_ij, Eigen::Matrix3d::Identity());
  // The triangle closes when no part of d_ik is out of the plane of d_ij and d_jk.
  t.coplanarity_deg = b.closes ? std::asin(std::min(1.0, std::abs(b.n.dot(b.d_ik)))) * kDeg : 90.0;

  const auto i_to_k = PairPartnersFrom(ik, i), j_to_k = PairPartnersFrom(jk, j);
  for (const auto& [a, c] : ij.matches) {
    const uint32_t fi = ij.image1 == i ? a : c, fj = ij.image1 == i ? c : a;
    const auto ci = i_to_k.find(fi), cj = j_to_k.find(fj);
    if (ci != i_to_k.end() && cj != j_to_k.end() && ci->second == cj->second) ++t.closed_matches;
  }
  return t;
}

bool FrameOfTriangle(uint32_t i, uint32_t j, uint32_t k, const PairEstimate& ij, const PairEstimate& ik,
                     const PairEstimate& jk, TriangleFrame* frame) {
  const TriangleBaselines b = BaselinesOf(i, j, ij, ik, jk);
  if (!b.closes) return false;
  frame->R = {Eigen::Matrix3d::Identity(), b.R_ij, PairRotationFrom(ik, i)};
  // C_k = d_ik / a from i, = d_ij + (b / a) d_jk from j: their mean.
  frame->C = {Eigen::Vector3d::Zero(), b.d_ij, 0.5 * (b.d_ik / b.ab(0) + b.d_ij + (b.ab(1) / b.ab(0)) * b.d_jk)};
  return true;
}

std::vector<int64_t> ConfirmWeakPairs(const std::vector<PairEstimate>& pairs,
                                      const TripletConfirmationOptions& options) {
  std::map<std::pair<uint32_t, uint32_t>, size_t> index;
  std::map<uint32_t, std::vector<uint32_t>> neighbours;  // sorted below: order-independent result
  for (size_t p = 0; p < pairs.size(); ++p) {
    const uint32_t a = pairs[p].image1, b = pairs[p].image2;
    index[{std::min(a, b), std::max(a, b)}] = p;
    neighbours[a].push_back(b);
    neighbours[b].push_back(a);
  }
  for (auto& [im, list] : neighbours) std::sort(list.begin(), list.end());
  const auto find = [&](uint32_t a, uint32_t b) -> const PairEstimate* {
    const auto it = index.find({std::min(a, b), std::max(a, b)});
    return it == index.end() ? nullptr : &pairs[it->second];
  };

  std::map<uint32_t, int> verified;  // image -> its pairs verified on their own
  for (const PairEstimate& p : pairs)
    if (!p.weak) ++verified[p.image1], ++verified[p.image2];
  const auto weakly_connected = [&](uint32_t im) {
    const auto it = verified.find(im);
    return it == verified.end() || it->second <= options.max_verified_pairs;
  };

  std::vector<int64_t> third(pairs.size(), -2);
  for (size_t p = 0; p < pairs.size(); ++p) {
    if (!pairs[p].weak) continue;
    third[p] = -1;
    const uint32_t i = pairs[p].image1, j = pairs[p].image2;
    if (!weakly_connected(i) && !weakly_connected(j)) continue;
    for (uint32_t k : neighbours[i]) {
      if (k == j) continue;
      const PairEstimate* ik = find(i, k);
      const PairEstimate* jk = find(j, k);
      if (!ik || !jk) continue;
      const TriangleTest t = TestTriangle(i, j, k, pairs[p], *ik, *jk);
      if (t.rotation_cycle_deg <= options.max_rotation_cycle_deg && t.coplanarity_deg <= options.max_coplanarity_deg &&
          t.closed_matches >= options.min_closed_matches) {
        third[p] = k;
        break;
      }
    }
  }
  if (options.keep_leaf_pairs) KeepLeafPairs(pairs, &third);
  return third;
}

}  // namespace pgba
