#include "modules/calibration/view_graph_calibration.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <stdexcept>

#include "pgba/io/option_ranges.h"
#include "modules/calibration/grid_search.h"
#include "modules/calibration/radial_distortion_search.h"
#include "modules/triplets/track_index.h"
#include "pgba/util/logging.h"
#include "pgba/util/text_format.h"
#include "pgba/util/timer.h"

namespace pgba {
namespace {

bool HasTwoFocals(CameraModel m) { return m == CameraModel::kPinhole || m == CameraModel::kOpenCV; }

// r^2 of eq. (1) for an essential matrix of rank <= 2.
double GapSquared(const Eigen::Matrix3d& E) {
  const double T = E.squaredNorm();
  // Sum of the squared 2x2 minors = |adj(E)|_F^2; adj(E)^T has columns c1 x c2, c2 x c0, c0 x c1.
  const double D = E.col(1).cross(E.col(2)).squaredNorm() + E.col(2).cross(E.col(0)).squaredNorm() +
                   E.col(0).cross(E.col(1)).squaredNorm();
  if (!(T > 0)) return 1.0;
  const double root = 2.0 * std::sqrt(D);
  return std::max(0.0, (T - root) / (T + root));
}

// A verified pair with its fundamental matrix in the prior-normalised coordinates of its
// cameras (x_hat = K_prior^-1 x): E for focal factors s1, s2 is diag(s2, s2, 1) F_hat
// diag(s1, s1, 1), since K(s) = K_prior diag(s, s, 1).
struct PairModel {
  uint32_t camera1 = 0, camera2 = 0;
  PairPixels pixels;  // raw pixels of the shared tracks; F of their pinhole pixels
  Eigen::Matrix3d F_hat = Eigen::Matrix3d::Zero();
  int inliers = 0;
  bool ok = false;
  bool planar = false;  // a homography explains the pair (HomographyInliers): not used
};

double PairGapSquared(const PairModel& m, double s1, double s2) {
  const Eigen::Vector3d d1(s1, s1, 1.0), d2(s2, s2, 1.0);
  return GapSquared(d2.asDiagonal() * m.F_hat * d1.asDiagonal());
}

void SetNormalisedF(const Camera& c1, const Camera& c2, const Eigen::Matrix3d& F, PairModel* model) {
  const Eigen::Matrix3d F_hat = PinholeMatrix(c2).transpose() * F * PinholeMatrix(c1);
  model->F_hat = F_hat / F_hat.norm();
  model->ok = model->F_hat.allFinite();
}

// Inliers of a homography x2 ~ H x1 (RANSAC, transfer error at the fundamental matrix's
// threshold). A pair whose correspondences a homography explains (a planar scene, or a
// rotation about the centre) has no unique F: RANSAC returns one of a family, and its
// singular values say nothing of the focal (Hartley & Zisserman, 13.3; COLMAP's and GLOMAP's
// "planar or panoramic" pairs, max_H_inlier_ratio 0.8).
int HomographyInliers(const std::vector<Eigen::Vector2d>& x1, const std::vector<Eigen::Vector2d>& x2,
                      const FundamentalMatrixOptions& options) {
  std::vector<cv::Point2d> p1(x1.size()), p2(x2.size());
  for (size_t i = 0; i < x1.size(); ++i) {
    p1[i] = {x1[i].x(), x1[i].y()};
    p2[i] = {x2[i].x(), x2[i].y()};
  }
  cv::Mat mask;
  const cv::Mat H = cv::findHomography(p1, p2, cv::RANSAC, options.threshold_px, mask, options.max_iterations,
                                       options.confidence);
  return H.empty() ? 0 : cv::countNonZero(mask);
}

PairModel EstimatePairModel(const TrackIndex& index, const TwoViewGeometry& pair,
                            const std::map<uint32_t, Camera>& cameras, const FundamentalMatrixOptions& options,
                            double max_homography_inlier_ratio) {
  PairModel model;
  const Reconstruction& tracks = index.tracks();
  model.camera1 = tracks.images.at(pair.image_id1).camera_id;
  model.camera2 = tracks.images.at(pair.image_id2).camera_id;
  const Camera& c1 = cameras.at(model.camera1);
  const Camera& c2 = cameras.at(model.camera2);
  for (const auto& [k1, k2] : index.SharedObservations(pair.image_id1, pair.image_id2)) {
    model.pixels.x1.push_back(index.Pixel(pair.image_id1, k1));
    model.pixels.x2.push_back(index.Pixel(pair.image_id2, k2));
  }
  // On the pixels undistorted by the current cameras (pixels of their pinhole part, so that
  // the RANSAC threshold stays in pixels).
  const FundamentalMatrixResult f =
      EstimateFundamentalMatrix(PinholePixels(c1, model.pixels.x1), PinholePixels(c2, model.pixels.x2), options);
  if (!f.success) return model;
  model.pixels.F = f.F;
  model.inliers = f.num_inliers;
  if (max_homography_inlier_ratio < 1.0 &&
      HomographyInliers(PinholePixels(c1, model.pixels.x1), PinholePixels(c2, model.pixels.x2), options) >=
          max_homography_inlier_ratio * f.num_inliers) {
    model.planar = true;  // F does not hold the focal: a family of F fits a homography
    return model;
  }
  SetNormalisedF(c1, c2, f.F, &model);
  return model;
}

bool DistortionFree(const Camera& c) {
  const int k = RadialCoefficientIndex(c.model);
  return k >= 0 && std::all_of(c.params.begin() + k, c.params.end(), [](double v) { return v == 0.0; });
}

// The cost of one camera's pairs with its factor exp(x), the others' factors as given.
class CameraCost {
 public:
  CameraCost(uint32_t camera, const std::vector<const PairModel*>& pairs, const std::map<uint32_t, double>& factors,
             double loss_scale)
      : camera_(camera), pairs_(pairs), factors_(factors), a2_(loss_scale * loss_scale) {}

  double operator()(double x) const {
    double sum = 0.0;
    for (const PairModel* p : pairs_) sum += a2_ * std::log1p(GapSquared(*p, x) / a2_);
    return sum;
  }
  double RmsGap(double x) const {
    double sum = 0.0;
    for (const PairModel* p : pairs_) sum += GapSquared(*p, x);
    return pairs_.empty() ? 0.0 : std::sqrt(sum / pairs_.size());
  }

 private:
  double GapSquared(const PairModel& p, double x) const {
    const double s = std::exp(x);
    const double s1 = p.camera1 == camera_ ? s : factors_.at(p.camera1);
    const double s2 = p.camera2 == camera_ ? s : factors_.at(p.camera2);
    return PairGapSquared(p, s1, s2);
  }
  uint32_t camera_;
  const std::vector<const PairModel*>& pairs_;
  const std::map<uint32_t, double>& factors_;
  double a2_;
};

// Gauss-Newton standard deviation of the minimiser x of a sum of n squared residuals C:
// var(x) = sigma^2 (J^T J)^-1 with J^T J ~ C'' / 2 and sigma^2 = C / (n - 1).
template <typename Cost>
double StandardDeviation(const Cost& cost, double x, int n) {
  if (n < 2) return INFINITY;
  const double h = 1e-2;
  const double c0 = cost(x);
  const double curvature = (cost(x + h) - 2.0 * c0 + cost(x - h)) / (h * h);
  if (!(curvature > 0)) return INFINITY;
  return std::sqrt(2.0 * (c0 / (n - 1)) / curvature);
}

}  // namespace

std::string ViewGraphCalibrationOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "calibration"); !m.empty()) return m;
  return "";
}

bool ViewGraphCalibrationResult::AnyApplied() const {
  return std::any_of(cameras.begin(), cameras.end(), [](const CameraFocalEstimate& c) { return c.applied; });
}

nlohmann::json ViewGraphCalibrationResult::ToJson() const {
  nlohmann::json list = nlohmann::json::array();
  for (const CameraFocalEstimate& c : cameras)
    list.push_back({{"camera_id", c.camera_id},
                    {"prior_focal", c.prior_focal},
                    {"estimated_focal", c.estimated_focal},
                    {"relative_sd", std::isfinite(c.relative_sd) ? nlohmann::json(c.relative_sd) : nlohmann::json()},
                    {"pairs_used", c.pairs_used},
                    {"rms_gap_prior", c.rms_gap_prior},
                    {"rms_gap_estimate", c.rms_gap_estimate},
                    {"k1_searched", c.k1_searched},
                    {"estimated_k1", c.estimated_k1},
                    {"sampson_cost_ratio", c.sampson_cost_ratio},
                    {"applied", c.applied},
                    {"reason", c.reason}});
  return {{"cameras", list},
          {"pairs_considered", pairs_considered},
          {"pairs_with_fundamental", pairs_with_fundamental},
          {"pairs_planar", pairs_planar},
          {"seconds", seconds}};
}

double SingularValueGapSquared(const Eigen::Matrix3d& F, const Camera& camera1, const Camera& camera2) {
  return GapSquared(PinholeMatrix(camera2).transpose() * F * PinholeMatrix(camera1));
}

Camera ScaleFocal(const Camera& camera, double scale) {
  Camera c = camera;
  c.params[0] *= scale;
  if (HasTwoFocals(c.model)) c.params[1] *= scale;
  return c;
}

ViewGraphCalibrationResult CalibrateFocalsFromViewGraph(const Reconstruction& tracks,
                                                        const std::vector<TwoViewGeometry>& pairs,
                                                        const ViewGraphCalibrationOptions& options,
                                                        std::map<uint32_t, Camera>* cameras) {
  const std::string problem = options.Check();
  if (!problem.empty()) throw std::invalid_argument("calibration." + problem);
  Timer timer;
  ViewGraphCalibrationResult result;
  std::map<uint32_t, double> factors;  // focal factor per camera w.r.t. the cameras as given
  for (const auto& [id, cam] : *cameras) {
    factors[id] = 1.0;
    const bool wanted = options.cameras == FocalEstimationCameras::kAll ||
                        (options.cameras == FocalEstimationCameras::kWeakPrior && !cam.has_prior_focal_length);
    if (!wanted) continue;
    CameraFocalEstimate c;
    c.camera_id = id;
    c.prior_focal = cam.MeanFocal();
    result.cameras.push_back(c);
  }
  if (result.cameras.empty()) return result;
  const auto estimated = [&](uint32_t id) {
    return std::any_of(result.cameras.begin(), result.cameras.end(),
                       [id](const CameraFocalEstimate& c) { return c.camera_id == id; });
  };

  std::vector<const TwoViewGeometry*> considered;
  for (const TwoViewGeometry& p : pairs)
    if (estimated(tracks.images.at(p.image_id1).camera_id) || estimated(tracks.images.at(p.image_id2).camera_id))
      considered.push_back(&p);
  result.pairs_considered = static_cast<int>(considered.size());
  const TrackIndex index(tracks);
  std::vector<PairModel> models(considered.size());
  tbb::parallel_for(size_t(0), considered.size(), [&](size_t i) {
    models[i] = EstimatePairModel(index, *considered[i], *cameras, options.fundamental,
                                  options.max_homography_inlier_ratio);
  });
  for (const PairModel& m : models) result.pairs_planar += m.planar;

  // Each camera's pairs, the best-supported first, capped.
  std::map<uint32_t, std::vector<const PairModel*>> pairs_of;
  for (const PairModel& m : models) {
    if (!m.ok) continue;
    ++result.pairs_with_fundamental;
    pairs_of[m.camera1].push_back(&m);
    if (m.camera2 != m.camera1) pairs_of[m.camera2].push_back(&m);
  }
  for (auto& [id, list] : pairs_of) {
    std::stable_sort(list.begin(), list.end(), [](const PairModel* a, const PairModel* b) { return a->inliers > b->inliers; });
    if (options.max_pairs_per_camera > 0 && list.size() > static_cast<size_t>(options.max_pairs_per_camera))
      list.resize(options.max_pairs_per_camera);
  }

  // The lens's k1 first (radial_distortion_search.h), for the distortion-free cameras with a
  // radial coefficient, from their pairs with themselves; their pairs' F are then refined
  // on the pixels undistorted with it.
  std::map<uint32_t, Camera> working = *cameras;
  for (CameraFocalEstimate& c : result.cameras) {
    const Camera& cam = cameras->at(c.camera_id);
    if (!options.estimate_k1 || !DistortionFree(cam)) continue;
    std::vector<const PairPixels*> own;
    for (const PairModel* m : pairs_of[c.camera_id])
      if (m->camera1 == m->camera2) own.push_back(&m->pixels);
    const RadialSearchResult k = SearchRadialDistortion(cam, own, options.fundamental, options.max_abs_k1);
    if (!k.searched || !(k.cost < k.cost_at_zero)) continue;
    working[c.camera_id].params[RadialCoefficientIndex(cam.model)] = k.k1;
    c.k1_searched = true;
    c.sampson_cost_ratio = k.cost_at_zero > 0 ? k.cost / k.cost_at_zero : 1.0;
  }
  tbb::parallel_for(size_t(0), models.size(), [&](size_t i) {
    PairModel& m = models[i];
    if (!m.ok) return;
    const Camera& w1 = working.at(m.camera1);
    const Camera& w2 = working.at(m.camera2);
    if (w1.params == cameras->at(m.camera1).params && w2.params == cameras->at(m.camera2).params) return;
    const FundamentalMatrixResult f =
        RefineFundamentalMatrix(PinholePixels(w1, m.pixels.x1), PinholePixels(w2, m.pixels.x2), m.pixels.F,
                                options.fundamental);
    if (f.success) SetNormalisedF(w1, w2, f.F, &m);
  });

  const double lo = std::log(options.min_focal_ratio), hi = std::log(options.max_focal_ratio);
  const int sweeps = result.cameras.size() > 1 ? options.max_sweeps : 1;
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    double largest_change = 0.0;
    for (CameraFocalEstimate& c : result.cameras) {
      const std::vector<const PairModel*>& list = pairs_of[c.camera_id];
      c.pairs_used = static_cast<int>(list.size());
      if (c.pairs_used < options.min_pairs) continue;
      const CameraCost cost(c.camera_id, list, factors, options.loss_scale);
      const GridMinimum m = MinimiseByGridAndGoldenSection(cost, lo, hi, 161, 1e-9);
      largest_change = std::max(largest_change, std::abs(m.x - std::log(factors[c.camera_id])));
      factors[c.camera_id] = std::exp(m.x);
      c.reason = m.at_bound ? "the minimum is at the bound of the search interval" : "";
    }
    if (largest_change < 1e-6) break;
  }

  for (CameraFocalEstimate& c : result.cameras) {
    const double x = std::log(factors[c.camera_id]);
    c.estimated_focal = c.prior_focal * factors[c.camera_id];
    const std::vector<const PairModel*>& list = pairs_of[c.camera_id];
    const CameraCost cost(c.camera_id, list, factors, options.loss_scale);  // at the final factors
    c.rms_gap_prior = cost.RmsGap(0.0);
    c.rms_gap_estimate = cost.RmsGap(x);
    c.relative_sd = StandardDeviation(cost, x, c.pairs_used);
    if (c.pairs_used < options.min_pairs) {
      c.reason = std::to_string(c.pairs_used) + " pairs with a fundamental matrix, " + std::to_string(options.min_pairs) +
                 " needed" +
                 (result.pairs_planar > 0 ? " (" + std::to_string(result.pairs_planar) +
                                                " pairs left out: a homography explains them, planar scene or pure "
                                                "rotation)"
                                          : std::string());
    } else if (c.reason.empty() && !(c.relative_sd <= options.max_relative_sd)) {
      c.reason = "the pairs' geometry does not determine it: sd " + FormatNumber("%.2g", 100 * c.relative_sd) +
                 "%, above calibration.max_relative_sd " + FormatNumber("%.2g", 100 * options.max_relative_sd) + "%";
    }
    c.applied = c.reason.empty();
    if (!c.applied) continue;
    // k1 was found in the prior's normalised coordinates u' = (x - c) / f'; the distorted
    // pixel radius f' r' (1 + k1' r'^2) is f r (1 + k1 r^2) with f = s f', r = r' / s:
    // k1 = k1' s^2.
    const double s = factors[c.camera_id];
    Camera updated = ScaleFocal(working.at(c.camera_id), s);
    const int k = RadialCoefficientIndex(updated.model);
    if (c.k1_searched) {
      updated.params[k] *= s * s;
      c.estimated_k1 = updated.params[k];
    }
    if (!updated.Validate().empty()) {  // cannot happen for a k1 valid at the prior focal; kept safe
      updated = ScaleFocal(cameras->at(c.camera_id), s);
      c.k1_searched = false;
      c.estimated_k1 = 0.0;
    }
    (*cameras)[c.camera_id] = updated;
  }
  result.seconds = timer.Seconds();
  return result;
}

}  // namespace pgba
