// How well a small bundle adjustment (a triplet's) determines the intrinsics it would
// estimate: the standard deviation of each free camera parameter from the normal equations of
// its reprojection residuals, the points Schur-eliminated and the similarity gauge held as
// the triplet BA holds it (anchor pose fixed, the scale image's centre on its sphere).
//
// Why: a triplet of narrow views (e.g. a ring around an object, 24 deg field of view) does
// not see its focal: focal and depth trade almost freely, the BA crawls along that valley
// until its iteration budget ends ("not converged") and the triplet is lost. Such a triplet
// keeps the current estimate; the global adjustments, which see all views, estimate it.
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "pgba/optim/intrinsics.h"
#include "pgba/scene/reconstruction.h"

namespace pgba {

struct IntrinsicsUncertainty {
  // The gauge-fixed reduced matrix of poses and intrinsics was positive definite.
  bool ok = false;
  // Per free parameter (cameras by ascending id, each one's free indices in order): its
  // standard deviation for 1 px observation noise, in the parameter's unit ...
  std::vector<double> stddev;
  // ... and as the shift of the farthest image corner it causes (pixels per pixel of noise).
  std::vector<double> stddev_px;
  // Largest of stddev_px, over all and per camera id (infinity when !ok): the test of
  // TripletOptions::intrinsics_max_sd_px.
  double max_stddev_px = 0.0;
  std::map<uint32_t, double> camera_max_stddev_px;
};

// At the current poses, points and cameras of `rec`: every observation of every point seen by
// two or more of `image_ids` (plain least squares, unit weight). `gauge_anchor` is held,
// `gauge_scale`'s centre keeps its distance to the anchor's. Deterministic.
IntrinsicsUncertainty EstimateIntrinsicsUncertainty(const Reconstruction& rec, const std::vector<uint32_t>& image_ids,
                                                    const FreeIntrinsics& free, uint32_t gauge_anchor,
                                                    uint32_t gauge_scale);

// |d pixel / d unknown| at the image corner farthest from the principal point, the corner's
// ray held (what a unit error of that unknown moves the image by, at most), the unknown
// moving the parameters along `direction` (a column of IntrinsicDirections).
double CornerPixelSensitivity(const Camera& camera, const Eigen::VectorXd& direction);

}  // namespace pgba
