// A rendered aerial block: photographs of a large textured ground with buildings, taken by
// a nadir (slightly tilted) camera flown in serpentine strips, with exact ground truth; the
// scale test of the image pipeline (a thousand photos through `pgba run`:
// bench/thousand_photos.sh).
//
// Geometry: flat ground z = 0 cut into 64 m tiles, each with its own procedural texture
// (procedural_texture.h), and box buildings (4-15 m high, textured walls and roofs, ~1.5
// per tile) that give every pair relief off the ground plane: a pair seeing one plane only
// has a two-fold relative pose ambiguity (rendered_scene.cc measured it in the room).
// Camera: image x across the flight line, image y along it, flown at
// altitude = focal x ground_sample_m, so the ground detail per pixel does not depend on the
// resolution; base and strip spacing follow from the overlaps. Attitude jitter (sd 2 deg
// about each axis) makes the views slightly oblique and the block not a perfect grid.
//
// Memory: the textures of the whole ground are held (3 bytes per texel at
// 0.8 x ground_sample_m: ~1 GB for 1,000 images at 1024 x 768, about 1 x 1 km; `pgba synth`
// peaked at 1.1 GB); images are rendered, encoded and written one per thread at a time
// (WriteAerialBlock), never all held.
// Deterministic: the same options give bit-identical files whatever the number of threads.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "modules/synthetic/ground_footprint.h"
#include "modules/synthetic/lens_remap.h"
#include "modules/synthetic/quad_renderer.h"
#include "modules/synthetic/rendered_scene.h"
#include "pgba/scene/reconstruction.h"

namespace pgba {

struct AerialBlockOptions {
  // seed, num_images, width, height, focal_px (0 = 0.8 x width), supersampling,
  // image_noise, k1, focal_prior_error as for the room (rendered_scene.h).
  RenderedSceneOptions image;
  int strips = 0;                 // flight lines; 0 = about as many as make the block square
  double forward_overlap = 0.75;  // along a strip, fraction of the footprint, [0.5, 0.9]
  double side_overlap = 0.5;      // between strips, [0.2, 0.8]
  double ground_sample_m = 0.1;   // ground distance of one pixel at nadir, metres
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};

// Defaults of the aerial scene where they differ from the room's: 1024 x 768 images, 1000 of
// them (the scale the scene exists for).
AerialBlockOptions DefaultAerialBlockOptions();

// InputError naming the option for unusable values.
void ValidateAerialBlockOptions(const AerialBlockOptions& options);

struct AerialBlock {
  // Camera 1 and images 1..n (strip by strip, in flight order) with their true poses.
  Reconstruction gt;
  Camera calibration;                                   // DIR/cameras.txt: gt's camera or its focal prior
  std::vector<synthetic::TexturedQuad> quads;           // ground tiles, then buildings
  std::vector<synthetic::GroundPolygon> footprints;     // per image, on z = 0
  std::shared_ptr<const synthetic::LensRenderer> lens;  // the true camera, built once
  int strips = 0;
  double altitude = 0.0;         // metres above the ground
  double extent = 0.0;           // diagonal of the bounding box of the camera centres
  double texture_seconds = 0.0;  // wall time of the geometry and the textures
};

AerialBlock MakeAerialBlock(const AerialBlockOptions& options);

// Image `k` (0-based: gt image k + 1), CV_8UC3, noise included.
cv::Mat RenderAerialImage(const AerialBlock& block, const AerialBlockOptions& options, size_t k);

// Pairs (i < j, 0-based image indices) whose footprints overlap by at least `min_overlap`
// (FootprintOverlap), sorted: the pairs pair selection should find.
std::vector<std::pair<uint32_t, uint32_t>> OverlappingPairs(const AerialBlock& block, double min_overlap);

// Renders and writes every image and the truth, in the layout of WriteRenderedScene:
//   DIR/images/<name>.png (replaced as a whole), DIR/cameras.txt, DIR/gt/,
//   DIR/overlap.txt: "name1 name2 overlap" for every pair with footprint overlap >= 0.1.
// Returns the wall time of rendering and writing the images.
double WriteAerialBlock(const AerialBlock& block, const AerialBlockOptions& options, const std::string& dir);

}  // namespace pgba
