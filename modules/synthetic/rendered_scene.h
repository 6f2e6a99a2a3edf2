// Rendered synthetic image scenes: photographs with exact ground truth, for testing and
// demonstrating the image front end (features, matching) and everything after it.
//
// The "room" scene: the inside of an 8 x 7 x 3 m room (floor, ceiling, four walls) with two
// stacked boxes in the middle, low boxes around them and furniture-like boxes along the
// walls (surfaces at many depths), every surface carrying its own procedural texture
// (procedural_texture.h). The cameras stand on a ring of radius ~2.4 m around the boxes,
// ~1.5 m high, each looking at the boxes, so that views see the boxes and the wall behind
// them; consecutive views overlap strongly and the ring closes (a loop). Images are rendered
// with quad_renderer.h (homography warps, z-buffer, 2x supersampling) plus Gaussian pixel
// noise.
//
// Everything is a function of the options: the same options give bit-identical images,
// whatever the number of threads.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "pgba/scene/reconstruction.h"

namespace pgba {

struct RenderedSceneOptions {
  uint64_t seed = 1;
  // Views on the ring (>= 3). 20 views are 18 degrees apart: each overlaps ~5 neighbours on
  // either side, enough for triplets all around the loop.
  int num_images = 20;
  int width = 640;
  int height = 480;
  // Focal length, pixels; 0 = 0.8 x width (a 64 degree horizontal field of view).
  double focal_px = 0.0;
  // Rendered samples per pixel and axis (anti-aliasing); 1 = none.
  int supersampling = 2;
  // Standard deviation of the Gaussian noise added to each 8-bit channel (sensor noise;
  // also keeps SIFT from locking onto perfectly flat regions).
  double image_noise = 1.5;
  // Radial distortion of the true lens (synthetic_lens.h; 0 = PINHOLE): the images are
  // rendered through it (lens_remap.h) and gt/cameras.txt holds SIMPLE_RADIAL with this k1.
  double k1 = 0.0;
  // Relative error of the focal of DIR/cameras.txt, the calibration handed to the pipeline
  // (its distortion is 0); gt/cameras.txt holds the truth. In [-0.5, 1].
  double focal_prior_error = 0.0;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};

// InputError naming the option for unusable values.
void ValidateRenderedSceneOptions(const RenderedSceneOptions& options);

struct RenderedScene {
  // Camera 1 (PINHOLE, or SIMPLE_RADIAL with k1; principal point at the image centre) and
  // images 1..n in ring order with their true poses; no points (the truth is the poses).
  Reconstruction gt;
  // The calibration written to DIR/cameras.txt: gt's camera, or its focal prior
  // (focal_prior_error, no distortion).
  Camera calibration;
  std::vector<cv::Mat> images;    // CV_8UC3 (BGR); images[k] is gt image k + 1
  std::vector<std::string> loop;  // image names in ring order; the last is adjacent to the first
  double extent = 0.0;            // diagonal of the bounding box of the camera centres, metres
  double seconds = 0.0;           // wall time of texturing and rendering
};

// The true camera of every rendered scene: camera 1, PINHOLE with focal_px (default 0.8 x
// width) and a centred principal point, then the radial distortion k1 (synthetic_lens.h).
Camera RenderedCamera(const RenderedSceneOptions& options);

RenderedScene RenderRoomScene(const RenderedSceneOptions& options);
// An object (a few textured boxes, 0.5 m across) in a plain room, seen all around from a ring:
// every feature lies on the object.
RenderedScene RenderObjectScene(const RenderedSceneOptions& options);

// Writes the layout of shared/datasets:
//   DIR/images/<name>.png   the photos (the folder is replaced as a whole)
//   DIR/cameras.txt         the calibration (COLMAP cameras.txt): scene.calibration
//   DIR/gt/                 COLMAP text model: cameras.txt, images.txt, empty points3D.txt
//   DIR/loop.txt            image names in ring order
// Every file is written atomically.
void WriteRenderedScene(const RenderedScene& scene, const std::string& dir);

}  // namespace pgba
