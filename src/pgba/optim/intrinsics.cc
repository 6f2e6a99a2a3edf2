#include "pgba/optim/intrinsics.h"
#include "pgba/io/option_ranges.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <stdexcept>
#include <type_traits>

namespace pgba {

namespace {

// Where the groups of COLMAP's parameter layouts sit (camera.h).
struct ParamGroups {
  std::vector<int> focal, principal_point, extra;
};

bool HasTwoFocals(CameraModel model) { return model == CameraModel::kPinhole || model == CameraModel::kOpenCV; }

ParamGroups GroupsOf(CameraModel model) {
  const int n = CameraModelNumParams(model);
  ParamGroups g;
  const int nf = HasTwoFocals(model) ? 2 : 1;
  for (int i = 0; i < nf; ++i) g.focal.push_back(i);
  g.principal_point = {nf, nf + 1};
  for (int i = nf + 2; i < n; ++i) g.extra.push_back(i);
  return g;
}

}  // namespace

const char* IntrinsicParamName(CameraModel model, int index) {
  static const char* kSimplePinhole[] = {"f", "cx", "cy"};
  static const char* kPinhole[] = {"fx", "fy", "cx", "cy"};
  static const char* kSimpleRadial[] = {"f", "cx", "cy", "k"};
  static const char* kRadial[] = {"f", "cx", "cy", "k1", "k2"};
  static const char* kOpenCV[] = {"fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2"};
  if (index < 0 || index >= CameraModelNumParams(model)) return "?";
  switch (model) {
    case CameraModel::kSimplePinhole:
      return kSimplePinhole[index];
    case CameraModel::kPinhole:
      return kPinhole[index];
    case CameraModel::kSimpleRadial:
      return kSimpleRadial[index];
    case CameraModel::kRadial:
      return kRadial[index];
    case CameraModel::kOpenCV:
      return kOpenCV[index];
  }
  return "?";
}

bool RefinesIntrinsics(const IntrinsicsOptions& options, bool calibration_is_prior) {
  switch (options.cameras) {
    case IntrinsicsCameras::kAll:
      return true;
    case IntrinsicsCameras::kNone:
      return false;
    case IntrinsicsCameras::kAuto:
      return calibration_is_prior;
  }
  return false;
}

std::vector<int> FreeIntrinsicIndices(CameraModel model, const IntrinsicsOptions& options) {
  const ParamGroups g = GroupsOf(model);
  std::vector<int> free;
  if (options.refine_focal_length)
    free.insert(free.end(), g.focal.begin(), options.refine_aspect_ratio ? g.focal.end() : g.focal.begin() + 1);
  if (options.refine_principal_point) free.insert(free.end(), g.principal_point.begin(), g.principal_point.end());
  if (options.refine_extra_params) free.insert(free.end(), g.extra.begin(), g.extra.end());
  return free;  // ascending: the groups follow each other in the layout
}

FreeIntrinsics SelectFreeIntrinsics(const std::map<uint32_t, Camera>& cameras, const IntrinsicsOptions& options) {
  FreeIntrinsics out;
  for (const auto& [id, camera] : cameras) {
    IntrinsicsOptions o = options;
    if (!camera.has_prior_focal_length && options.refine_principal_point_without_calibration)
      o.refine_principal_point = true;
    std::vector<int> free = FreeIntrinsicIndices(camera.model, o);
    if (!free.empty()) out[id] = std::move(free);
  }
  return out;
}

Eigen::MatrixXd IntrinsicDirections(const Camera& camera, const std::vector<int>& free) {
  const int n = static_cast<int>(camera.params.size());
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(n, static_cast<int>(free.size()));
  const bool fy_free = std::find(free.begin(), free.end(), 1) != free.end();
  for (size_t j = 0; j < free.size(); ++j) {
    d(free[j], static_cast<int>(j)) = 1.0;
    if (free[j] == 0 && HasTwoFocals(camera.model) && !fy_free) d(1, static_cast<int>(j)) = camera.params[1] / camera.params[0];
  }
  return d;
}

Eigen::VectorXd GatherIntrinsics(const Camera& camera, const std::vector<int>& free) {
  Eigen::VectorXd v(free.size());
  for (size_t i = 0; i < free.size(); ++i) v(i) = camera.params[free[i]];
  return v;
}

void ScatterIntrinsics(const Eigen::VectorXd& values, const std::vector<int>& free, Camera* camera) {
  const Eigen::VectorXd change = IntrinsicDirections(*camera, free) * (values - GatherIntrinsics(*camera, free));
  for (int i = 0; i < change.size(); ++i) camera->params[i] += change(i);
  // The unknowns' own parameters exactly (not x + (v - x), which may differ in the last bit).
  for (size_t i = 0; i < free.size(); ++i) camera->params[free[i]] = values(i);
}

namespace {

// x + D delta on the parameter block, D = IntrinsicDirections (n x k, full column rank: each
// column holds its own parameter's 1). Minus is D's left inverse, exact on the manifold.
class LinearIntrinsicsManifold : public ceres::Manifold {
 public:
  explicit LinearIntrinsicsManifold(Eigen::MatrixXd directions)
      : d_(std::move(directions)), left_inverse_((d_.transpose() * d_).ldlt().solve(d_.transpose())) {}
  int AmbientSize() const override { return static_cast<int>(d_.rows()); }
  int TangentSize() const override { return static_cast<int>(d_.cols()); }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    const Eigen::Map<const Eigen::VectorXd> dv(delta, d_.cols());
    for (int i = 0; i < d_.rows(); ++i) x_plus_delta[i] = x[i] + d_.row(i).dot(dv);
    return true;
  }
  bool PlusJacobian(const double*, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(jacobian, d_.rows(), d_.cols()) =
        d_;
    return true;
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    const Eigen::Map<const Eigen::VectorXd> yv(y, d_.rows()), xv(x, d_.rows());
    Eigen::Map<Eigen::VectorXd>(y_minus_x, d_.cols()) = left_inverse_ * (yv - xv);
    return true;
  }
  bool MinusJacobian(const double*, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(jacobian, d_.cols(), d_.rows()) =
        left_inverse_;
    return true;
  }

 private:
  Eigen::MatrixXd d_, left_inverse_;
};

}  // namespace

ceres::Manifold* IntrinsicsManifold(const Camera& camera, const std::vector<int>& free) {
  const int n = static_cast<int>(camera.params.size());
  if (static_cast<int>(free.size()) == n) return nullptr;
  if (free.empty()) {  // all held (the caller sets such a block constant)
    std::vector<int> all(n);
    for (int i = 0; i < n; ++i) all[i] = i;
    return new ceres::SubsetManifold(n, all);
  }
  return new LinearIntrinsicsManifold(IntrinsicDirections(camera, free));
}

ceres::CostFunction* CreateReprojectionErrorWithIntrinsics(CameraModel model, const Eigen::Matrix3d& R0,
                                                           const Eigen::Vector2d& pixel, double weight) {
  auto make = [&](auto size) -> ceres::CostFunction* {
    constexpr int n = decltype(size)::value;
    using F = ReprojectionErrorWithIntrinsics;
    return new ceres::AutoDiffCostFunction<F, 2, 6, 3, n>(new F(model, R0, pixel, weight));
  };
  switch (CameraModelNumParams(model)) {
    case 3:
      return make(std::integral_constant<int, 3>());
    case 4:
      return make(std::integral_constant<int, 4>());
    case 5:
      return make(std::integral_constant<int, 5>());
    case 8:
      return make(std::integral_constant<int, 8>());
  }
  throw std::invalid_argument("camera model with an unexpected parameter count");
}

std::string IntrinsicsOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "intrinsics"); !m.empty()) return m;
  return "";
}

}  // namespace pgba
