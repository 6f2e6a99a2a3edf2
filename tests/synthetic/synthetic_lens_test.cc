// Lens options of the synthetic scenes (synthetic_lens.h, lens_remap.h), against their exact
// truth: observations are the true distorted projections, the input calibration is the
// announced focal prior without distortion, a non-invertible k1 is refused, and the renderer
// draws a world point where the distorted camera projects it.
#include <gtest/gtest.h>

#include <cmath>

#include "modules/synthetic/lens_remap.h"
#include "modules/synthetic/rendered_scene.h"
#include "modules/synthetic/synthetic_layout.h"
#include "modules/synthetic/synthetic_lens.h"
#include "pgba/util/error.h"
#include "tests/synthetic/synthetic_test_helpers.h"

namespace pgba {
namespace {

SyntheticScene GenerateWithLens(SyntheticScenario scenario, double k1, double focal_prior_error, double noise = 0.0) {
  SyntheticOptions o;
  o.scenario = scenario;
  o.noise_px = noise;
  o.k1 = k1;
  o.focal_prior_error = focal_prior_error;
  o.num_images = scenario == SyntheticScenario::kAerial ? 24 : 20;
  return GenerateSyntheticScene(o);
}

class EveryScenarioWithLens : public ::testing::TestWithParam<SyntheticScenario> {};

TEST_P(EveryScenarioWithLens, ObservationsAreTheDistortedProjectionsAndTheInputIsThePrior) {
  const double k1 = -0.08, error = 0.15;
  const SyntheticScene s = GenerateWithLens(GetParam(), k1, error);
  const Camera& truth = s.gt.cameras.at(1);
  const Camera& prior = s.input.cameras.at(1);
  // The truth: SIMPLE_RADIAL (OPENCV for the two-focal planar camera) with k1.
  if (GetParam() == SyntheticScenario::kPlanar) {
    ASSERT_EQ(truth.model, CameraModel::kOpenCV);
    EXPECT_EQ(truth.params[4], k1);
    EXPECT_EQ(prior.params[4], 0.0);
    EXPECT_DOUBLE_EQ(prior.params[1], 1.15 * truth.params[1]);
  } else {
    ASSERT_EQ(truth.model, CameraModel::kSimpleRadial);
    EXPECT_EQ(truth.params[3], k1);
    EXPECT_EQ(prior.params[3], 0.0);
  }
  EXPECT_EQ(prior.model, truth.model);
  EXPECT_DOUBLE_EQ(prior.params[0], 1.15 * truth.params[0]);
  EXPECT_EQ(prior.params[1 + (truth.model == CameraModel::kOpenCV)], truth.params[1 + (truth.model == CameraModel::kOpenCV)]);
  // Every noiseless observation is its point's projection through the distortion, and its
  // undistorted ray is the point's (no point folded into the image from outside the field).
  size_t checked = 0;
  double max_err = 0.0, max_ray_err = 0.0, max_shift = 0.0;
  for (const auto& [id, im] : s.gt.images) {
    const Image& in = s.input.images.at(id);
    ASSERT_EQ(in.points2D.size(), im.points2D.size());
    for (size_t k = 0; k < im.points2D.size(); ++k) {
      const Eigen::Vector3d x = im.pose.ToCamera(s.gt.points3D.at(im.points2D[k].point3D_id).xyz);
      const Eigen::Vector2d u = x.head<2>() / x.z();
      const double r2 = u.squaredNorm();
      Eigen::Vector2d expected;  // u (1 + k1 r^2), then the pinhole part, written out
      if (truth.model == CameraModel::kOpenCV) {
        expected << truth.params[0] * u.x() * (1 + k1 * r2) + truth.params[2],
            truth.params[1] * u.y() * (1 + k1 * r2) + truth.params[3];
      } else {
        expected = truth.params[0] * u * (1 + k1 * r2) + Eigen::Vector2d(truth.params[1], truth.params[2]);
      }
      max_err = std::max(max_err, (im.points2D[k].xy - expected).norm());
      Eigen::Vector2d back;
      ASSERT_TRUE(truth.UndistortPixel(im.points2D[k].xy, &back));
      max_ray_err = std::max(max_ray_err, (back - u).norm());
      max_shift = std::max(max_shift, (expected - prior.Project(x)).norm());
      EXPECT_EQ(in.points2D[k].xy, im.points2D[k].xy);
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000u);
  EXPECT_LT(max_err, 1e-6);
  EXPECT_LT(max_ray_err, 1e-9);
  EXPECT_GT(max_shift, 10.0) << "the prior camera must not explain the observations";
}

INSTANTIATE_TEST_SUITE_P(Synthetic, EveryScenarioWithLens,
                         ::testing::Values(SyntheticScenario::kOrbit, SyntheticScenario::kAerial,
                                           SyntheticScenario::kPlanar),
                         [](const auto& info) { return std::string(SyntheticScenarioName(info.param)); });

TEST(SyntheticLens, WithoutLensOptionsInputAndTruthShareThePinhole) {
  const SyntheticScene s = GenerateWithLens(SyntheticScenario::kOrbit, 0.0, 0.0);
  EXPECT_EQ(s.gt.cameras.at(1).model, CameraModel::kPinhole);
  EXPECT_EQ(s.input.cameras.at(1).params, s.gt.cameras.at(1).params);
}

TEST(SyntheticLens, UnusableLensOptionsAreInputErrors) {
  const auto message = [](double k1, double error) -> std::string {
    try {
      GenerateWithLens(SyntheticScenario::kOrbit, k1, error);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  // Barrel k1 = -0.9 folds before the corners of the 1920x1080, f 1163 px image.
  EXPECT_NE(message(-0.9, 0.0).find("not invertible"), std::string::npos) << message(-0.9, 0.0);
  EXPECT_NE(message(1.5, 0.0).find("k1"), std::string::npos);
  EXPECT_NE(message(NAN, 0.0).find("k1"), std::string::npos);
  EXPECT_NE(message(0.0, -0.6).find("focal_prior_error"), std::string::npos);
  EXPECT_NE(message(0.0, NAN).find("focal_prior_error"), std::string::npos);
  EXPECT_EQ(message(-0.08, 0.15), "");
}

TEST(LensRenderer, OutputPixelsSampleTheCanvasAlongTheirOwnRay) {
  Camera cam;
  cam.model = CameraModel::kSimpleRadial;
  cam.width = 320;
  cam.height = 240;
  cam.params = {256.0, 161.0, 118.0, -0.08};
  const synthetic::LensRenderer lens(cam, 2);
  // Rays across the whole image, corners included: the canvas pixel of an output pixel is
  // the pinhole canvas's projection of the ray the camera projects there.
  for (const Eigen::Vector3d& x : {Eigen::Vector3d(0.0, 0.0, 1.0), Eigen::Vector3d(-0.55, 0.42, 1.0),
                                   Eigen::Vector3d(0.55, -0.4, 1.0), Eigen::Vector3d(0.58, 0.42, 1.0)}) {
    const Eigen::Vector2d pixel = cam.Project(x);
    ASSERT_GE(pixel.x(), 0.0);
    ASSERT_LE(pixel.x(), cam.width);
    ASSERT_GE(pixel.y(), 0.0);
    ASSERT_LE(pixel.y(), cam.height);
    EXPECT_LT((lens.CanvasPixelOf(pixel) - lens.canvas().Project(x)).norm(), 1e-8) << x.transpose();
    const Eigen::Vector2d c = lens.canvas().Project(x);
    EXPECT_GE(c.x(), 0.0);  // inside the canvas
    EXPECT_GE(c.y(), 0.0);
    EXPECT_LE(c.x(), lens.canvas().width);
    EXPECT_LE(c.y(), lens.canvas().height);
  }
  // Barrel distortion: the canvas holds more than the supersampled pinhole image would.
  EXPECT_GT(lens.canvas().width, 2 * cam.width);
}

TEST(RenderedSceneLens, TruthIsDistortedAndTheCalibrationIsThePrior) {
  RenderedSceneOptions o;
  o.num_images = 3;
  o.width = 160;
  o.height = 120;
  o.k1 = -0.08;
  o.focal_prior_error = -0.15;
  const RenderedScene scene = RenderRoomScene(o);
  const Camera& truth = scene.gt.cameras.at(1);
  ASSERT_EQ(truth.model, CameraModel::kSimpleRadial);
  EXPECT_EQ(truth.params[0], 0.8 * 160);
  EXPECT_EQ(truth.params[3], -0.08);
  EXPECT_EQ(scene.calibration.model, CameraModel::kSimpleRadial);
  EXPECT_DOUBLE_EQ(scene.calibration.params[0], 0.85 * 0.8 * 160);
  EXPECT_EQ(scene.calibration.params[3], 0.0);
  ASSERT_EQ(scene.images.size(), 3u);
  EXPECT_EQ(scene.images[0].cols, 160);
  o.k1 = -0.9;  // folds inside the 64 degree field of view
  EXPECT_THROW(RenderRoomScene(o), InputError);
}

}  // namespace
}  // namespace pgba
