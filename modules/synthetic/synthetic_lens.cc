#include "modules/synthetic/synthetic_lens.h"

#include <cmath>

#include "pgba/util/error.h"

namespace pgba::synthetic {

Camera WithRadialDistortion(const Camera& pinhole, double k1, const std::string& option) {
  if (!std::isfinite(k1)) ThrowInputError(option, 0, "must be a finite number");
  if (k1 == 0.0) return pinhole;
  const std::vector<double>& p = pinhole.params;
  Camera cam = pinhole;
  switch (pinhole.model) {
    case CameraModel::kSimplePinhole:
      cam.model = CameraModel::kSimpleRadial;
      cam.params = {p[0], p[1], p[2], k1};
      break;
    case CameraModel::kPinhole:
      if (p[0] == p[1]) {
        cam.model = CameraModel::kSimpleRadial;
        cam.params = {p[0], p[2], p[3], k1};
      } else {
        cam.model = CameraModel::kOpenCV;
        cam.params = {p[0], p[1], p[2], p[3], k1, 0.0, 0.0, 0.0};
      }
      break;
    default:
      ThrowInputError(option, 0, "needs a pinhole base camera, got " + std::string(CameraModelName(pinhole.model)));
  }
  const std::string problem = cam.Validate();
  if (!problem.empty())
    ThrowInputError(option, 0, "k1 = " + std::to_string(k1) + " is unusable for a " + std::to_string(cam.width) + "x" +
                                   std::to_string(cam.height) + " image with focal " +
                                   std::to_string(cam.MeanFocal()) + " px: " + problem);
  return cam;
}

Camera FocalPrior(const Camera& truth, double relative_error) {
  Camera prior = truth;
  const double scale = 1.0 + relative_error;
  switch (truth.model) {
    case CameraModel::kSimplePinhole:
    case CameraModel::kSimpleRadial:
    case CameraModel::kRadial:
      prior.params[0] *= scale;
      for (size_t k = 3; k < prior.params.size(); ++k) prior.params[k] = 0.0;
      break;
    case CameraModel::kPinhole:
    case CameraModel::kOpenCV:
      prior.params[0] *= scale;
      prior.params[1] *= scale;
      for (size_t k = 4; k < prior.params.size(); ++k) prior.params[k] = 0.0;
      break;
  }
  return prior;
}

void ValidateLensOptions(double k1, const std::string& k1_option, double focal_prior_error,
                         const std::string& error_option) {
  if (!(std::abs(k1) <= 1.0))
    ThrowInputError(k1_option, 0, "must be a finite number in [-1, 1], got " + std::to_string(k1));
  if (!(focal_prior_error >= -0.5 && focal_prior_error <= 1.0))
    ThrowInputError(error_option, 0,
                    "must be a relative error in [-0.5, 1] (0.15: prior 15% too long), got " +
                        std::to_string(focal_prior_error));
}

}  // namespace pgba::synthetic
