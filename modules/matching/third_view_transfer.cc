#include "matching/third_view_transfer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

namespace pgba {
namespace {

// A pair's matches as feature -> partner, from each side.
struct Partners {
  std::unordered_map<uint32_t, uint32_t> of_x, of_z;  // x's feature -> z's, z's -> x's
};

Partners PartnersOf(const PairEstimate& p, uint32_t x) {
  return {PairPartnersFrom(p, x), PairPartnersFrom(p, p.image1 == x ? p.image2 : p.image1)};
}

void AddMatch(PairEstimate* p, uint32_t x, uint32_t fx, uint32_t fz) {
  if (p->image1 == x)
    p->matches.emplace_back(fx, fz);
  else
    p->matches.emplace_back(fz, fx);
}

// Midpoint of two rays (origin, unit direction), false when they are parallel to within
// `min_angle` (radians) or the point is behind either origin.
bool Midpoint(const Eigen::Vector3d& o1, const Eigen::Vector3d& d1, const Eigen::Vector3d& o2,
              const Eigen::Vector3d& d2, double min_angle, Eigen::Vector3d* X) {
  const double c = d1.dot(d2);
  if (1.0 - c * c < std::sin(min_angle) * std::sin(min_angle)) return false;
  const Eigen::Vector3d w = o1 - o2;
  const double s1 = (c * d2.dot(w) - d1.dot(w)) / (1.0 - c * c);
  const double s2 = (d2.dot(w) - c * d1.dot(w)) / (1.0 - c * c);
  if (s1 <= 0 || s2 <= 0) return false;
  *X = 0.5 * (o1 + s1 * d1 + o2 + s2 * d2);
  return true;
}

// (x, y, z): pair (x, y) of a triangle transfers into view z.
constexpr std::array<std::array<int, 3>, 3> kRoles{{{0, 1, 2}, {0, 2, 1}, {1, 2, 0}}};

}  // namespace

std::vector<int> TransferIntoThirdViews(std::vector<PairEstimate>* pairs, const std::map<uint32_t, TransferView>& views,
                                        double focal_px, const GuidedMatchingOptions& options) {
  std::map<std::pair<uint32_t, uint32_t>, size_t> index;
  std::map<uint32_t, std::vector<uint32_t>> neighbours;
  for (size_t p = 0; p < pairs->size(); ++p) {
    const uint32_t a = (*pairs)[p].image1, b = (*pairs)[p].image2;
    index[{std::min(a, b), std::max(a, b)}] = p;
    neighbours[std::min(a, b)].push_back(std::max(a, b));
  }
  for (auto& [im, list] : neighbours) std::sort(list.begin(), list.end());
  const auto slot = [&](uint32_t a, uint32_t b) -> long {
    const auto it = index.find({std::min(a, b), std::max(a, b)});
    return it == index.end() ? -1 : static_cast<long>(it->second);
  };
  const double cos_threshold = std::cos(std::atan(options.threshold_px / focal_px));
  const double min_ray_angle = 0.25 * M_PI / 180.0;  // as TripletOptions::min_track_angle_deg
  std::vector<int> added(pairs->size(), 0);

  for (const auto& [i, above] : neighbours)
    for (size_t u = 0; u < above.size(); ++u)
      for (size_t v = u + 1; v < above.size(); ++v) {
        const uint32_t j = above[u], k = above[v];
        const long s_ij = slot(i, j), s_ik = slot(i, k), s_jk = slot(j, k);
        if (s_jk < 0) continue;
        TriangleFrame frame;
        if (!FrameOfTriangle(i, j, k, (*pairs)[s_ij], (*pairs)[s_ik], (*pairs)[s_jk], &frame)) continue;
        const std::array<uint32_t, 3> image{i, j, k};
        const std::array<long, 3> pair_of{s_jk, s_ik, s_ij};  // the pair opposite each view
        // Pair (x, y) transfers into view z, for z = k, j, i.
        for (const auto& [x, y, z] : kRoles) {
          PairEstimate& xy = (*pairs)[pair_of[z]];
          PairEstimate& xz = (*pairs)[pair_of[y]];
          PairEstimate& yz = (*pairs)[pair_of[x]];
          Partners in_xz = PartnersOf(xz, image[x]), in_yz = PartnersOf(yz, image[y]);
          const TransferView& vx = views.at(image[x]);
          const TransferView& vy = views.at(image[y]);
          const TransferView& vz = views.at(image[z]);
          const std::vector<Eigen::Vector3d>& bz = *vz.bearings;
          const size_t num_matches = xy.matches.size();
          for (size_t m = 0; m < num_matches; ++m) {
            const auto [a, b] = xy.matches[m];
            const uint32_t fx = xy.image1 == image[x] ? a : b, fy = xy.image1 == image[x] ? b : a;
            if (in_xz.of_x.count(fx) || in_yz.of_x.count(fy)) continue;
            Eigen::Vector3d X;
            if (!Midpoint(frame.C[x], frame.R[x].transpose() * (*vx.bearings)[fx], frame.C[y],
                          frame.R[y].transpose() * (*vy.bearings)[fy], min_ray_angle, &X))
              continue;
            const Eigen::Vector3d in_z = frame.R[z] * (X - frame.C[z]);
            if (in_z.z() <= 0) continue;
            const Eigen::Vector3d predicted = in_z.normalized();
            NearestTwo nearest;
            const uint8_t* dx = vx.descriptors->ptr<uint8_t>(static_cast<int>(fx));
            for (size_t c = 0; c < bz.size(); ++c) {
              if (bz[c].dot(predicted) < cos_threshold) continue;
              if (in_xz.of_z.count(static_cast<uint32_t>(c)) || in_yz.of_z.count(static_cast<uint32_t>(c))) continue;
              nearest.Offer(static_cast<int>(c), SiftDistance(dx, vz.descriptors->ptr<uint8_t>(static_cast<int>(c))));
            }
            if (!nearest.Passes(options)) continue;
            const uint32_t fz = static_cast<uint32_t>(nearest.index);
            AddMatch(&xz, image[x], fx, fz);
            AddMatch(&yz, image[y], fy, fz);
            in_xz.of_x.emplace(fx, fz);
            in_xz.of_z.emplace(fz, fx);
            in_yz.of_x.emplace(fy, fz);
            in_yz.of_z.emplace(fz, fy);
            ++added[pair_of[y]];
            ++added[pair_of[x]];
          }
        }
      }
  for (PairEstimate& p : *pairs) std::sort(p.matches.begin(), p.matches.end());
  return added;
}

}  // namespace pgba
