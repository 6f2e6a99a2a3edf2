#include "pgba/optim/intrinsics.h"

#include <stdexcept>
#include <type_traits>

namespace pgba {

namespace {

// Where the groups of COLMAP's parameter layouts sit (camera.h).
struct ParamGroups {
  std::vector<int> focal, principal_point, extra;
};

ParamGroups GroupsOf(CameraModel model) {
  const int n = CameraModelNumParams(model);
  ParamGroups g;
  const bool one_focal = model == CameraModel::kSimplePinhole || model == CameraModel::kSimpleRadial ||
                         model == CameraModel::kRadial;
  const int nf = one_focal ? 1 : 2;
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
  if (options.refine_focal_length) free.insert(free.end(), g.focal.begin(), g.focal.end());
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

Eigen::VectorXd GatherIntrinsics(const Camera& camera, const std::vector<int>& free) {
  Eigen::VectorXd v(free.size());
  for (size_t i = 0; i < free.size(); ++i) v(i) = camera.params[free[i]];
  return v;
}

void ScatterIntrinsics(const Eigen::VectorXd& values, const std::vector<int>& free, Camera* camera) {
  for (size_t i = 0; i < free.size(); ++i) camera->params[free[i]] = values(i);
}

ceres::Manifold* HeldIntrinsicsManifold(int num_params, const std::vector<int>& free) {
  if (static_cast<int>(free.size()) == num_params) return nullptr;
  std::vector<int> held;
  for (int i = 0, j = 0; i < num_params; ++i) {
    if (j < static_cast<int>(free.size()) && free[j] == i) {
      ++j;
    } else {
      held.push_back(i);
    }
  }
  return new ceres::SubsetManifold(num_params, held);
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

}  // namespace pgba
