#include "matching/essential_ransac.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include <opengv/relative_pose/CentralRelativeAdapter.hpp>
#include <opengv/relative_pose/methods.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "pgba/io/option_ranges.h"
#include "matching/relative_pose.h"
#include "matching/relative_pose_method.h"

namespace pgba {
namespace {

// Bail-out granularity: the partial loss is compared with the best every this many points.
constexpr size_t kBailOutStride = 32;
// Local optimisation (LO-RANSAC, Chum et al. 2003) of every new best model: re-weighted
// linear fits on its inliers, at most kLoIterations of them on at most kLoMaxPoints evenly
// spaced inliers. It raises the best inlier ratio early, which is what stops the sampling.
constexpr int kLoIterations = 3;
constexpr size_t kLoMaxPoints = 256;
// A 5-point solution whose imaginary part exceeds this fraction of its real part is complex.
constexpr double kMaxImaginary = 1e-8;

// Minimal samples of 5 distinct indices from a seeded engine (deterministic per seed).
class Sampler {
 public:
  Sampler(uint64_t seed, size_t n) : rng_(seed), dist_(0, n - 1) {}
  void Draw(std::vector<size_t>* s) {
    s->clear();
    while (s->size() < 5) {
      const size_t k = dist_(rng_);
      if (std::find(s->begin(), s->end(), k) == s->end()) s->push_back(k);
    }
  }

 private:
  std::mt19937_64 rng_;
  std::uniform_int_distribution<size_t> dist_;
};

// The cost of a correspondence of squared Sampson angle e2: 1 + its MSAC loss min(e2, th2)
// scaled by `s` = 1 / (th2 (n + 1)) for an outlier, the scaled loss alone for an inlier. The
// sum ranks models by their number of outliers first and by the MSAC loss (under 1 in all)
// among those with as many: measured on the rendered room, the MSAC loss alone preferred a
// tight fit of 40 of a weak pair's 52 matches (a wrong pose) to the right one of 43.
inline double Cost(double e2, double th2, double s) { return e2 < th2 ? e2 * s : 1.0 + th2 * s; }

// The summed cost of E, or a value above `bail` as soon as the partial sum exceeds it.
double Loss(const Eigen::Matrix3d& E, const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2,
            double th2, double s, double bail) {
  double loss = 0.0;
  const size_t n = b1.size();
  for (size_t i = 0; i < n; ++i) {
    loss += Cost(SampsonAngleSquared(E, b1[i], b2[i]), th2, s);
    if ((i + 1) % kBailOutStride == 0 && loss > bail) return loss;
  }
  return loss;
}

int Inliers(const Eigen::Matrix3d& E, const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2,
            double th2, std::vector<size_t>* idx) {
  idx->clear();
  for (size_t i = 0; i < b1.size(); ++i)
    if (SampsonAngleSquared(E, b1[i], b2[i]) < th2) idx->push_back(i);
  return static_cast<int>(idx->size());
}

// The nearest essential matrix (singular values 1, 1, 0).
Eigen::Matrix3d ProjectToEssential(const Eigen::Matrix3d& M) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return svd.matrixU() * Eigen::Vector3d(1, 1, 0).asDiagonal() * svd.matrixV().transpose();
}

// Linear least squares of b2^T E b1 over `idx`, each row weighted by 1 / the Sampson
// denominator under `E0` (so the algebraic error approximates the Sampson one).
Eigen::Matrix3d WeightedLinearFit(const Eigen::Matrix3d& E0, const std::vector<Eigen::Vector3d>& b1,
                                  const std::vector<Eigen::Vector3d>& b2, const std::vector<size_t>& idx) {
  Eigen::Matrix<double, 9, 9> AtA = Eigen::Matrix<double, 9, 9>::Zero();
  const size_t m = std::min(idx.size(), kLoMaxPoints);
  for (size_t k = 0; k < m; ++k) {
    const size_t i = idx[k * idx.size() / m];
    const Eigen::Vector3d Eb1 = E0 * b1[i], Etb2 = E0.transpose() * b2[i];
    const double g = b2[i].dot(Eb1);
    const double denom = Eb1.squaredNorm() + Etb2.squaredNorm() - 2.0 * g * g;
    if (!(denom > 1e-300)) continue;
    Eigen::Matrix<double, 9, 1> a;  // row-major vec(E): a . vec(E) = b2^T E b1
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) a(3 * r + c) = b2[i](r) * b1[i](c);
    AtA.noalias() += (a / denom) * a.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> eig(AtA);
  const Eigen::Matrix<double, 9, 1> e = eig.eigenvectors().col(0);
  Eigen::Matrix3d E;
  E << e(0), e(1), e(2), e(3), e(4), e(5), e(6), e(7), e(8);
  return ProjectToEssential(E);
}

// Of the four (R, t) of E, the one with the most of `idx` in front of both cameras.
int Decompose(const Eigen::Matrix3d& E, const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2,
              const std::vector<size_t>& idx, double parallel_angle, Eigen::Matrix3d* R_out, Eigen::Vector3d* t_out) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(E, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU(), V = svd.matrixV();
  if (U.determinant() < 0) U = -U;
  if (V.determinant() < 0) V = -V;
  Eigen::Matrix3d W;
  W << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  const Eigen::Matrix3d Rs[2] = {U * W * V.transpose(), U * W.transpose() * V.transpose()};
  int best = -1;
  for (const Eigen::Matrix3d& R : Rs)
    for (double sign : {1.0, -1.0}) {
      const Eigen::Vector3d t = sign * U.col(2);
      int front = 0;
      for (size_t i : idx) front += InFrontOfBoth(R, t, b1[i], b2[i], parallel_angle);
      if (front > best) {
        best = front;
        *R_out = R;
        *t_out = t;
      }
    }
  return best;
}

int RequiredIterations(double inlier_ratio, double confidence, int max_iterations) {
  const double w5 = std::pow(inlier_ratio, 5);
  if (w5 >= 1.0) return 0;
  if (w5 <= 0.0) return max_iterations;
  const double k = std::log(1.0 - confidence) / std::log(1.0 - w5);
  return k >= max_iterations ? max_iterations : static_cast<int>(std::ceil(k));
}

}  // namespace

EssentialRansacResult EssentialRansac(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2,
                                      const EssentialRansacOptions& options) {
  const bool nister = ParsePoseSolver(options.algorithm) == PoseSolver::kNister;
  EssentialRansacResult result;
  const size_t n = b1.size();
  if (n < 5 || b2.size() != n) return result;
  const double th2 = options.threshold_angle * options.threshold_angle;
  const double s = 1.0 / (th2 * static_cast<double>(n + 1));
  opengv::bearingVectors_t f1(b1.begin(), b1.end()), f2(b2.begin(), b2.end());
  opengv::relative_pose::CentralRelativeAdapter adapter(f1, f2);
  Sampler sampler(options.seed, n);
  std::vector<size_t> sample, idx;
  std::vector<int> sample_int(5);
  double best_loss = std::numeric_limits<double>::infinity();
  int best_inliers = 0;
  int needed = options.max_iterations;
  int it = 0;
  std::vector<size_t> candidate_idx;
  // Keeps E if its loss beats the best: counts its inliers and updates the iteration bound.
  // The Sampson error cannot tell a point in front of both cameras from one behind: on a
  // nearly planar scene a wrong E (the plane's twin) can fit as many matches as the true
  // one. So a candidate that beats the best is decomposed, and its inliers behind a camera
  // count as outliers (rendered room: without this 3 of its verified pairs had a pose of
  // a ~0.3 degree triangulation angle that the tracks' view graph then rejected). Only the
  // few candidates that beat the best pay for it.
  const auto consider = [&](const Eigen::Matrix3d& E) {
    if (!E.allFinite()) return false;
    double loss = Loss(E, b1, b2, th2, s, best_loss);
    if (!(loss < best_loss)) return false;
    Inliers(E, b1, b2, th2, &candidate_idx);
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    if (Decompose(E, b1, b2, candidate_idx, options.threshold_angle, &R, &t) <= 0) return false;
    size_t front = 0;
    for (size_t i : candidate_idx)
      if (InFrontOfBoth(R, t, b1[i], b2[i], options.threshold_angle)) candidate_idx[front++] = i;
      else loss += Cost(th2, th2, s) - Cost(SampsonAngleSquared(E, b1[i], b2[i]), th2, s);
    candidate_idx.resize(front);
    if (!(loss < best_loss)) return false;
    best_loss = loss;
    result.E_21 = E;
    result.R_21 = R;
    result.t_21 = t;
    idx.swap(candidate_idx);
    best_inliers = static_cast<int>(idx.size());
    needed = std::max(options.min_iterations, RequiredIterations(double(best_inliers) / double(n), options.confidence,
                                                                 options.max_iterations));
    return true;
  };
  for (; it < std::min(needed, options.max_iterations); ++it) {
    sampler.Draw(&sample);
    for (int k = 0; k < 5; ++k) sample_int[k] = static_cast<int>(sample[k]);
    opengv::essentials_t Es;
    if (nister) {
      Es = opengv::relative_pose::fivept_nister(adapter, sample_int);
    } else {
      // Stewenius' solver returns the complex roots too: their real parts are no essential
      // matrices (a near rank-1 one has a zero Sampson error on whole bands of matches and
      // can beat the true E on a weak pair), so they are skipped.
      for (const auto& Ec : opengv::relative_pose::fivept_stewenius(adapter, sample_int))
        if (Ec.imag().norm() <= kMaxImaginary * Ec.real().norm()) Es.push_back(Ec.real());
    }
    bool improved = false;
    // OpenGV's E is [t_12]x R_12 with b1^T E b2 = 0, i.e. E_21 = E^T.
    // Projected on the essential manifold: the solvers' E are so only up to round-off.
    for (const Eigen::Matrix3d& E12 : Es) improved |= consider(ProjectToEssential(E12.transpose()));
    if (!improved || best_inliers < 8) continue;
    for (int lo = 0; lo < kLoIterations; ++lo)
      if (!consider(WeightedLinearFit(result.E_21, b1, b2, idx))) break;
  }
  result.iterations = it;
  result.num_inliers = best_inliers;
  result.success = best_inliers >= 5;
  return result;
}

std::string EssentialRansacOptions::Check() const {
  const std::string m = CheckRangesAt({{"threshold_angle", threshold_angle}, {"algorithm", algorithm},
                                       {"max_iterations", max_iterations}, {"confidence", confidence},
                                       {"min_iterations", min_iterations}},
                                      "EssentialRansacOptions");
  if (!m.empty()) return m;
  if (min_iterations > max_iterations) return "min_iterations: must not exceed max_iterations";
  return "";
}

}  // namespace pgba
