#include "mapper/pair_alignment.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <tuple>

#include "pgba/geometry/rotation.h"
#include "pgba/util/text_format.h"

namespace pgba {
namespace {

// A verified pair oriented from model a's image to model b's: R_ab maps a's camera frame to
// b's, t_ab = R_b (C_a - C_b) up to a positive scale.
struct BridgePair {
  uint32_t a = 0, b = 0;
  Eigen::Matrix3d R_ab;
  Eigen::Vector3d t_ab;
};

std::vector<BridgePair> BridgePairs(const std::vector<TwoViewGeometry>& pairs, const std::map<uint32_t, Pose>& a,
                                    const std::map<uint32_t, Pose>& b) {
  auto only = [](const std::map<uint32_t, Pose>& in, const std::map<uint32_t, Pose>& out, uint32_t id) {
    return in.count(id) && !out.count(id);
  };
  std::vector<BridgePair> bridges;
  for (const TwoViewGeometry& p : pairs) {
    if (only(a, b, p.image_id1) && only(b, a, p.image_id2)) {
      bridges.push_back({p.image_id1, p.image_id2, p.R_21, p.t_21.normalized()});
    } else if (only(b, a, p.image_id1) && only(a, b, p.image_id2)) {
      bridges.push_back({p.image_id2, p.image_id1, p.R_21.transpose(), (-(p.R_21.transpose() * p.t_21)).normalized()});
    }
  }
  std::sort(bridges.begin(), bridges.end(),
            [](const BridgePair& x, const BridgePair& y) { return std::tie(x.a, x.b) < std::tie(y.a, y.b); });
  return bridges;
}

// Centroid and RMS distance from it of the centres of `poses` (the normalised frame).
struct Normalisation {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double scale = 1.0;
};
Normalisation NormalisationOf(const std::map<uint32_t, Pose>& poses) {
  Normalisation n;
  for (const auto& [id, pose] : poses) n.centroid += pose.C();
  n.centroid /= static_cast<double>(poses.size());
  double sum = 0.0;
  for (const auto& [id, pose] : poses) sum += (pose.C() - n.centroid).squaredNorm();
  n.scale = std::sqrt(sum / static_cast<double>(poses.size()));
  if (!(n.scale > 0.0)) n.scale = 1.0;
  return n;
}

double AngleDeg(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v)) * 180.0 / M_PI;
}

}  // namespace

ModelAlignment AlignModelsByPairs(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                                  const std::map<uint32_t, Pose>& a, const std::map<uint32_t, Pose>& b,
                                  const PairAlignmentOptions& options, const ImageVerificationOptions& verification) {
  ModelAlignment result;
  result.by = MergeEvidence::kVerifiedPairs;
  const std::vector<BridgePair> bridges = BridgePairs(pairs, a, b);
  const int n = static_cast<int>(bridges.size());
  result.pairs = n;
  if (n < options.min_pairs) {
    result.reason = std::to_string(n) + " verified pairs between the models (fewer than " +
                    std::to_string(options.min_pairs) + ")";
    return result;
  }
  // Each pair's rotation of the similarity; the largest set within the tolerance of one of
  // them (the first such pair on a tie), then its chordal mean and the pairs within the
  // tolerance of that.
  std::vector<Eigen::Matrix3d> rotations;
  for (const BridgePair& p : bridges)
    rotations.push_back(a.at(p.a).R().transpose() * p.R_ab.transpose() * b.at(p.b).R());
  auto agreeing_with = [&](const Eigen::Matrix3d& R) {
    std::vector<int> agree;
    for (int j = 0; j < n; ++j)
      if (RotationAngleDeg(R, rotations[j]) <= options.max_rotation_deg) agree.push_back(j);
    return agree;
  };
  std::vector<int> agree;
  for (int i = 0; i < n; ++i) {
    std::vector<int> candidate = agreeing_with(rotations[i]);
    if (candidate.size() > agree.size()) agree = std::move(candidate);
  }
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (int j : agree) sum += rotations[j];
  const Eigen::Matrix3d R = ClosestRotation(sum);
  agree = agreeing_with(R);
  result.agreeing_pairs = static_cast<int>(agree.size());
  const std::string tolerance = FormatNumber("%.3g", options.max_rotation_deg) + " deg";
  if (result.agreeing_pairs < options.min_pairs || result.agreeing_pairs < options.min_agreeing_ratio * n) {
    result.reason = std::to_string(result.agreeing_pairs) + " of " + std::to_string(n) +
                    " verified pairs between the models agree on their rotation (within " + tolerance + ")";
    return result;
  }
  // Scale and translation: s R C_b + t - lambda_i d_i = C_a for every agreeing pair, in the
  // normalised frames (C = centroid + scale * c) so that the unknowns are of one magnitude.
  const Normalisation na = NormalisationOf(a), nb = NormalisationOf(b);
  const int k = result.agreeing_pairs;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(3 * k, 4 + k);
  Eigen::VectorXd rhs(3 * k);
  std::vector<Eigen::Vector3d> directions;
  for (int r = 0; r < k; ++r) {
    const BridgePair& p = bridges[agree[r]];
    const Pose& pose_b = b.at(p.b);
    // C_b - C_a = -R_b^T t_ab (camera b's frame to B's world), in A's frame by R.
    const Eigen::Vector3d d = (R * (-(pose_b.R().transpose() * p.t_ab))).normalized();
    directions.push_back(d);
    M.block<3, 1>(3 * r, 0) = R * ((pose_b.C() - nb.centroid) / nb.scale);
    M.block<3, 3>(3 * r, 1) = Eigen::Matrix3d::Identity();
    M.block<3, 1>(3 * r, 4 + r) = -d;
    rhs.segment<3>(3 * r) = (a.at(p.a).C() - na.centroid) / na.scale;
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(M, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& singular = svd.singularValues();
  const double conditioning = singular(singular.size() - 1) / singular(0);
  result.conditioning = conditioning;
  if (M.rows() < M.cols() || !(conditioning >= kMinConditioning)) {
    result.reason = "the " + std::to_string(k) + " verified pairs between the models do not fix the scale (their baselines " +
                    "conditioned at " + FormatNumber("%.2g", std::max(conditioning, 0.0)) + ")";
    return result;
  }
  const Eigen::VectorXd x = svd.solve(rhs);
  Sim3 sim;
  sim.R = R;
  sim.s = na.scale * x(0) / nb.scale;
  sim.t = na.centroid + na.scale * x.segment<3>(1) - sim.s * (R * nb.centroid);
  if (!(sim.s > 0.0) || !std::isfinite(sim.s) || !sim.t.allFinite()) {
    result.reason = "the verified pairs between the models give no positive scale";
    return result;
  }
  result.b_to_a = sim;
  // Every baseline forward; with redundant pairs each along its direction.
  const bool redundant = M.rows() > M.cols();
  for (int r = 0; r < k; ++r) {
    const BridgePair& p = bridges[agree[r]];
    const Eigen::Vector3d baseline = sim.Apply(b.at(p.b).C()) - a.at(p.a).C();
    const std::string names = tracks.images.at(p.a).name + " - " + tracks.images.at(p.b).name;
    if (!(x(4 + r) > 0.0)) {
      result.reason = "pair " + names + ": the merged centres lie behind its baseline";
      return result;
    }
    const double off = AngleDeg(baseline, directions[r]);
    if (redundant && off > options.max_direction_deg) {
      result.reason = "pair " + names + ": its baseline is " + FormatNumber("%.3g", off) +
                      " deg off the direction the other pairs give (more than " +
                      FormatNumber("%.3g", options.max_direction_deg) + " deg)";
      return result;
    }
  }
  // The merged model passes the verification at every image of the agreeing pairs.
  std::map<uint32_t, Pose> merged = a;
  for (const auto& [id, pose] : b) merged.emplace(id, sim.Apply(pose));
  std::set<uint32_t> bridge_images;
  for (int r : agree) {
    bridge_images.insert(bridges[r].a);
    bridge_images.insert(bridges[r].b);
  }
  for (uint32_t id : bridge_images) {
    const ImageEvidence evidence = MeasureImageEvidence(tracks, pairs, merged, id, merged.at(id), verification);
    const std::string failure = VerificationFailure(evidence, verification);
    if (!failure.empty()) {
      result.reason = "image " + tracks.images.at(id).name + " fails the verification in the merged model: " + failure;
      return result;
    }
  }
  result.success = true;
  return result;
}

}  // namespace pgba
