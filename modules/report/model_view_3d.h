// The 3D view of report.html: every model's cameras as frusta and its points, drawn by three.js
// in the reader's browser (model_view_3d.js; both inlined, so the page stays self-contained).
//
// Each model is shown in a frame of its own, the view frame: centred on its cameras and points,
// scaled to a radius of 1 and turned so that its up direction is +y (three.js's up): the
// cameras' common up direction when they are held upright, the opposite of their common viewing
// direction when they look down on a flat scene (an aerial block). Models share no frame (each
// component of the view graph is adjusted on its own, with a scale of its own), so several are
// laid side by side along x, the largest first.
//
// The data goes into the page as compact JSON with fixed precision (coordinates as integers of
// a fixed unit): the same models give the same bytes whatever the thread count.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "pgba/scene/reconstruction.h"

namespace pgba {

struct ModelView3dOptions {
  // Points shown at most (about: every k-th point of each model, in id order, above it).
  size_t max_points = 200000;
  // A frustum's depth: this fraction of the median distance from a camera to its nearest
  // neighbour, within [0.03, 0.15] of the model's radius.
  double frustum_fraction = 0.5;
};

struct ModelView3d {
  struct Model {
    size_t images = 0, points = 0;
    // World frame -> view frame: scale * rotation * (X - centre) + offset.
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();
    double scale = 1.0;
    double frustum_depth = 0.0;  // view units
    Eigen::Vector3d ToView(const Eigen::Vector3d& X) const { return scale * (rotation * (X - centre)) + offset; }
  };
  struct Camera {
    std::string name;
    int model = 0;
    // Median reprojection error (px) of the image's observations of its model's points (one
    // behind the camera: infinite); NaN when it observes none.
    double residual_px = 0.0;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // view frame
    // The image's corners (top-left, top-right, bottom-right, bottom-left) at the frustum's
    // depth, view frame.
    std::array<Eigen::Vector3d, 4> corners;
  };
  std::vector<Model> models;
  std::vector<Camera> cameras;          // model by model, each in image id order
  std::vector<Eigen::Vector3d> points;  // view frame: every point_step-th point of each model
  // The colours of `points`; empty when no point has a colour of its own (all COLMAP's
  // default grey, as the pipeline triangulates them).
  std::vector<Eigen::Matrix<uint8_t, 3, 1>> colours;
  size_t points_total = 0;  // of every model
  size_t point_step = 1;
  // The residual colour scale runs from 0 to this: the largest finite image residual, 1 px at
  // least.
  double residual_scale_px = 1.0;
};

// The view of `models` (largest first; empty or cameraless models are left out).
ModelView3d MakeModelView3d(const std::vector<const Reconstruction*>& models, const ModelView3dOptions& options = {});

// The page's data: {"camera_unit", "point_unit", "models": [{"images", "points", "offset",
// "colour"}], "residual_scale", "residual_colours", "cameras": [{"name", "model", "residual",
// "frustum": centre and corners as 15 integers of camera_unit}], "points": integers of
// point_unit, "colours": "rrggbb" per point (absent without colours)}. No "<" (an image name's
// is escaped), so it cannot end its <script> element.
std::string ModelView3dJson(const ModelView3d& view);

// The section of report.html: heading, how to move the view, the notes (several models,
// points left out), the legend, the view's box and its data. Without a camera it says so.
std::string ModelView3dSection(const ModelView3d& view);
// The scripts that draw it (three.js, OrbitControls, model_view_3d.js), for the end of the
// page; "" without a camera.
std::string ModelView3dScripts(const ModelView3d& view);

}  // namespace pgba
