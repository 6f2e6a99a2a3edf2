// A focal length prior, in pixels, from a photo's EXIF (read with libexif), for folders that
// come without a calibration file. Its own file because it is the one place pgba reads
// image metadata; the image catalog (image_catalog.h) turns the priors into cameras.
//
// The rules are COLMAP's (Bitmap::ExifFocalLength), so that pgba starts from the focal
// COLMAP would start from:
//   1. FocalLengthIn35mmFilm f35: per the CIPA definition of the 35 mm equivalent (a ratio of
//      diagonals), f_px = f35 / 43.27 mm * diagonal_px. For a 3:2 image this is
//      f35 / 36 mm * max(width, height); for 4:3 images it is 4% longer than that.
//   2. FocalLength f_mm with FocalPlaneXResolution + FocalPlaneResolutionUnit (pixels per
//      inch / cm / mm / um on the sensor): f_px = f_mm * pixels_per_mm. Like COLMAP, the
//      resolution is taken at face value (an image resized after capture gets a wrong focal
//      from this rule; rule 1 is unaffected).
//   COLMAP then looks the sensor width up in its camera database by EXIF Make/Model; pgba has
//   no such database, so a photo with FocalLength alone gets the default.
//   3. Default: 1.2 * max(width, height), COLMAP's prior (a 45 degree field of view across the
//      longer side).
// A focal outside [0.1, 100] * max(width, height) (fields of view of ~180 to ~0.6 degrees) is
// taken as a broken tag and replaced by the default.
#pragma once

#include <string>

namespace pgba {

enum class FocalSource { kExif35mm, kExifFocalPlane, kDefault };

// "EXIF FocalLengthIn35mmFilm", "EXIF FocalLength + FocalPlaneXResolution", "default prior".
const char* FocalSourceName(FocalSource source);

struct FocalPrior {
  double focal_px = 0.0;
  FocalSource source = FocalSource::kDefault;
  // Why EXIF that was present was not used (corrupt block, implausible value); "" otherwise
  // (including "no EXIF at all", the normal case of a PNG).
  std::string problem;
};

// 1.2 * max(width, height).
double DefaultFocalPx(int width, int height);

// The prior of the image file at `path`, whose decoded size is width x height. Never throws
// and never crashes on bad metadata: a missing, truncated or corrupt EXIF block gives the
// default (with `problem` set when something was there but unusable).
FocalPrior ExifFocalPrior(const std::string& path, int width, int height);

}  // namespace pgba
