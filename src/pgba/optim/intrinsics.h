// Self-calibration (paper, "Self-calibrating bundle adjustment"): which of a camera's COLMAP
// parameters (camera.h layouts) a bundle adjustment estimates, with COLMAP's switches, and the
// reprojection residual that takes them as a parameter block. Intrinsics are per camera,
// shared by all its images; every adjustment (point-based, triplet, local BA, local Hessians,
// pointless global BA) uses the same selection, so that their unknowns agree.
#pragma once

#include <string>

#include <ceres/ceres.h>

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <vector>

#include "pgba/optim/pose_parameterization.h"
#include "pgba/scene/camera.h"

namespace pgba {

// Which cameras get intrinsic unknowns.
enum class IntrinsicsCameras {
  // Those whose calibration is only a prior: `pgba run` without a calibration file (focal from
  // EXIF or 1.2 max(w, h), no distortion). A calibration the user gives is held (a lab
  // calibration is better than what a block can estimate of itself).
  kAuto,
  kAll,   // every camera (e.g. tracks whose cameras.txt holds only a prior)
  kNone,  // none: the calibration is exact
};
NLOHMANN_JSON_SERIALIZE_ENUM(IntrinsicsCameras, {{IntrinsicsCameras::kAuto, "auto"},
                                                 {IntrinsicsCameras::kAll, "all"},
                                                 {IntrinsicsCameras::kNone, "none"}})

struct IntrinsicsOptions {
  IntrinsicsCameras cameras = IntrinsicsCameras::kAuto;
  // COLMAP's switches and defaults: the focal (f, or fx and fy) and the distortion
  // coefficients are estimated, the principal point is not (it is weakly determined and
  // correlates with the rotations; COLMAP holds it unless asked).
  bool refine_focal_length = true;
  bool refine_principal_point = false;
  bool refine_extra_params = true;
  // A model with two focals (PINHOLE, OPENCV) estimates one focal unknown with fy / fx held at
  // the prior's ratio unless this is set (then fx and fy apart, as COLMAP does). Pixels are
  // square on every camera pgba has met, and on a ring or a narrow block one of the two is
  // not observable on its own: temple_sparse_ring with a 10% PINHOLE prior, fx and fy apart,
  // left fx at a standard deviation of 4-16% and 1-6% off while fy came within 0.6% (docs/measurement_history.md,
  // issue 14).
  bool refine_aspect_ratio = false;
  // A camera without any calibration (no file, no EXIF: its focal is the 1.2 max(w, h) guess,
  // Camera::has_prior_focal_length false) also estimates its principal point, unlike COLMAP:
  // real lenses put it 15-17 px (0.3-0.5 deg) off the image centre, which no focal or
  // distortion absorbs. Measured on the four real sets without calibration (docs/measurement_history.md, issue 14):
  // the rotation error falls 1.3-4.8x (Sim3) and 1.2-3.8x (gauge-free) on every one of them.
  // Applies to the adjustments after the triplets (a triplet never frees it).
  bool refine_principal_point_without_calibration = true;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(IntrinsicsOptions, cameras, refine_focal_length,
                                                refine_principal_point, refine_extra_params,
                                                refine_aspect_ratio,
                                                refine_principal_point_without_calibration)

// Whether the cameras get unknowns: options.cameras resolved for a calibration that is a
// prior (true) or given (false).
bool RefinesIntrinsics(const IntrinsicsOptions& options, bool calibration_is_prior);

// Indices into Camera::params estimated for this model under the switches, ascending. With
// the aspect ratio held, a two-focal model lists fx alone: its unknown moves fy with it
// (IntrinsicDirections).
std::vector<int> FreeIntrinsicIndices(CameraModel model, const IntrinsicsOptions& options);

// COLMAP's name of parameter `index` of the model ("f", "cx", "k", "fx", "k1", "p2", ...).
const char* IntrinsicParamName(CameraModel model, int index);

// Camera id -> its free parameter indices; cameras without any are absent (empty: all held).
// The principal point of a camera without calibration follows
// refine_principal_point_without_calibration.
using FreeIntrinsics = std::map<uint32_t, std::vector<int>>;
FreeIntrinsics SelectFreeIntrinsics(const std::map<uint32_t, Camera>& cameras, const IntrinsicsOptions& options);

// How the unknowns move the camera's parameters: column j is the change of Camera::params per
// unit of unknown j, the unit vector of free[j], except for the focal of a two-focal model
// whose fy is not free (the aspect ratio held): then fx's unknown moves fy by fy / fx of the
// camera as given, so the ratio stays the prior's. Every Jacobian with respect to the
// intrinsics is the parameters' Jacobian times this matrix.
Eigen::MatrixXd IntrinsicDirections(const Camera& camera, const std::vector<int>& free);

// The unknowns' values of `camera` (its parameters at `free`'s indices) and back: Scatter
// moves the parameters along IntrinsicDirections by the change of the unknowns.
Eigen::VectorXd GatherIntrinsics(const Camera& camera, const std::vector<int>& free);
void ScatterIntrinsics(const Eigen::VectorXd& values, const std::vector<int>& free, Camera* camera);

// The Ceres manifold of the camera's full parameter block on which only the unknowns move,
// along IntrinsicDirections (nullptr when every parameter is its own unknown); the caller
// sets the block constant when `free` is empty.
ceres::Manifold* IntrinsicsManifold(const Camera& camera, const std::vector<int>& free);

// Pixel reprojection residual with the camera parameters as a block: (pose[6], point[3],
// params[n]), n = CameraModelNumParams(model). The same projection as ReprojectionError.
struct ReprojectionErrorWithIntrinsics {
  ReprojectionErrorWithIntrinsics(CameraModel model, const Eigen::Matrix3d& R0, const Eigen::Vector2d& pixel,
                                  double weight)
      : model(model), R0(R0), pixel(pixel), weight(weight) {}

  template <typename T>
  bool operator()(const T* pose, const T* X, const T* params, T* residual) const {
    T xc[3];
    WorldToCamera(R0, pose, X, xc);
    T px[2];
    ProjectToPixel(model, params, xc, px);
    residual[0] = T(weight) * (px[0] - T(pixel.x()));
    residual[1] = T(weight) * (px[1] - T(pixel.y()));
    return true;
  }

  CameraModel model;
  Eigen::Matrix3d R0;
  Eigen::Vector2d pixel;
  double weight;
};

// The residual above for the camera's model (blocks: pose, point, the camera's full params).
ceres::CostFunction* CreateReprojectionErrorWithIntrinsics(CameraModel model, const Eigen::Matrix3d& R0,
                                                           const Eigen::Vector2d& pixel, double weight = 1.0);

}  // namespace pgba
