#include "report/model_view_3d.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "pgba/util/text_format.h"
#include "report/embedded_scripts.h"
#include "report/view_graph_svg.h"

namespace pgba {
namespace {

// The view's units: points to 1/1000 of a model's radius (a pixel of a view 1000 px wide),
// cameras to 1/10000 (the frusta of a dense block are a few hundredths of it).
constexpr double kPointUnit = 1e-3;
constexpr double kCameraUnit = 1e-4;
// The models' centres along x, in view units (each has a radius of 1).
constexpr double kModelSpacing = 2.6;
// The residual colour scale, low to high (blue, purple, red), and the colour of a camera
// without a residual: the model's JSON and the legend share them.
const char* const kResidualColours[] = {"#2166ac", "#7b3294", "#d7191c"};
constexpr const char* kNoResidualColour = "#999999";

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

// The median over the points of the distance to the nearest other point (0 for fewer than two).
// A sweep along x: a neighbour farther in x than the best distance so far is not looked at.
double MedianNearestDistance(std::vector<Eigen::Vector3d> c) {
  if (c.size() < 2) return 0.0;
  std::sort(c.begin(), c.end(), [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::tie(a.x(), a.y(), a.z()) < std::tie(b.x(), b.y(), b.z());
  });
  std::vector<double> nearest(c.size());
  for (size_t i = 0; i < c.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();  // squared
    for (size_t j = i + 1; j < c.size() && (c[j].x() - c[i].x()) * (c[j].x() - c[i].x()) < best; ++j)
      best = std::min(best, (c[j] - c[i]).squaredNorm());
    for (size_t j = i; j-- > 0 && (c[i].x() - c[j].x()) * (c[i].x() - c[j].x()) < best;)
      best = std::min(best, (c[j] - c[i]).squaredNorm());
    nearest[i] = std::sqrt(best);
  }
  return Percentile(nearest, 0.5);
}

// The principal axes of `points` weighted by `weights`, least spread first (columns).
Eigen::Matrix3d PrincipalAxes(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& weights) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  double total = 0.0;
  for (size_t i = 0; i < points.size(); ++i) mean += weights[i] * points[i], total += weights[i];
  mean /= std::max(total, 1e-300);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < points.size(); ++i) cov += weights[i] * (points[i] - mean) * (points[i] - mean).transpose();
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors();
}

// The rotation whose rows are the view's x, y (up) and z axes in the model's world frame.
Eigen::Matrix3d ViewRotation(const Reconstruction& model) {
  Eigen::Vector3d up_sum = Eigen::Vector3d::Zero(), look_sum = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> cameras, points;
  for (const auto& [id, im] : model.images) {
    const Eigen::Matrix3d R = im.pose.R();
    up_sum -= R.row(1).transpose();  // image y points down
    look_sum += R.row(2).transpose();
    cameras.push_back(im.pose.C());
  }
  for (const auto& [id, p] : model.points3D) points.push_back(p.xyz);
  const double n = static_cast<double>(cameras.size());
  const Eigen::Vector3d up_mean = up_sum / n, look_mean = look_sum / n;
  // The scene's axes: of cameras and points, the cameras weighing as much as all the points.
  std::vector<Eigen::Vector3d> all = cameras;
  all.insert(all.end(), points.begin(), points.end());
  std::vector<double> weights(cameras.size(), points.empty() ? 1.0 : static_cast<double>(points.size()) / n);
  weights.resize(all.size(), 1.0);
  const Eigen::Matrix3d axes = PrincipalAxes(all, weights);
  // The points' thinnest axis: a flat scene's normal.
  const Eigen::Vector3d flat =
      points.size() >= 3 ? Eigen::Vector3d(PrincipalAxes(points, std::vector<double>(points.size(), 1.0)).col(0))
                         : Eigen::Vector3d(axes.col(0));
  Eigen::Vector3d up;
  if (look_mean.norm() > 0.7 && std::abs(look_mean.normalized().dot(flat)) > 0.8) {
    up = -look_mean.normalized();  // looking down on a flat scene
  } else if (up_mean.norm() > 0.5) {
    up = up_mean.normalized();  // held upright
  } else if (look_mean.norm() > 0.5) {
    up = -look_mean.normalized();
  } else {
    Eigen::Vector3d cam_mean = Eigen::Vector3d::Zero(), point_mean = Eigen::Vector3d::Zero();
    for (const auto& c : cameras) cam_mean += c / n;
    for (const auto& p : points) point_mean += p / static_cast<double>(points.size());
    up = axes.col(0);
    if ((cam_mean - point_mean).dot(up) < 0) up = -up;  // the cameras above
  }
  Eigen::Vector3d x = axes.col(2) - axes.col(2).dot(up) * up;
  if (x.norm() < 1e-6) x = axes.col(1) - axes.col(1).dot(up) * up;
  x.normalize();
  Eigen::Matrix3d rotation;
  rotation.row(0) = x.transpose();
  rotation.row(1) = up.transpose();
  rotation.row(2) = x.cross(up).transpose();
  return rotation;
}

// Normalised image coordinates (x/z, y/z) of the image's corners: top-left, top-right,
// bottom-right, bottom-left. Where the distortion cannot be undone, the pinhole's.
std::array<Eigen::Vector2d, 4> CornerRays(const Camera& camera) {
  const double f = std::max(camera.MeanFocal(), 1e-9);
  // Without a size: a field of view of about 53 degrees, 4:3.
  const double w = camera.width > 0 ? camera.width : f, h = camera.height > 0 ? camera.height : 0.75 * w;
  const Eigen::Vector2d pixels[4] = {{0.0, 0.0}, {w, 0.0}, {w, h}, {0.0, h}};
  std::array<Eigen::Vector2d, 4> rays;
  for (int k = 0; k < 4; ++k) {
    Eigen::Vector2d n;
    if (camera.width <= 0 || camera.height <= 0 || !camera.UndistortPixel(pixels[k], &n) || !n.allFinite())
      n = (pixels[k] - Eigen::Vector2d(w / 2, h / 2)) / f;
    rays[k] = n;
  }
  return rays;
}

// Median reprojection error per image id of its observations of the model's points (images with
// none absent). The median: a few gross errors (a point near an image's plane reprojects
// thousands of pixels away) would make the mean of a good image look bad.
std::map<uint32_t, double> ImageResiduals(const Reconstruction& model) {
  std::map<uint32_t, std::vector<double>> errors;
  for (const auto& [pid, p] : model.points3D)
    for (const TrackElement& e : p.track) {
      const auto im = model.images.find(e.image_id);
      if (im == model.images.end() || e.point2D_idx >= im->second.points2D.size()) continue;
      const Eigen::Vector3d x_cam = im->second.pose.ToCamera(p.xyz);
      const double r = x_cam.z() > 0
                           ? (model.CameraOf(im->second).Project(x_cam) - im->second.points2D[e.point2D_idx].xy).norm()
                           : std::numeric_limits<double>::infinity();  // behind the camera
      errors[e.image_id].push_back(std::isfinite(r) ? r : std::numeric_limits<double>::infinity());
    }
  std::map<uint32_t, double> median;
  for (auto& [id, v] : errors) median[id] = Percentile(std::move(v), 0.5);
  return median;
}

void AddModel(const Reconstruction& model, int index, size_t point_step, const ModelView3dOptions& options,
              ModelView3d* view) {
  ModelView3d::Model m;
  m.images = model.images.size();
  m.points = model.points3D.size();
  m.rotation = ViewRotation(model);
  // Centre and radius: the box of the cameras and of the 2nd..98th percentiles of the points
  // along each view axis (a few far points do not shrink the model).
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& [id, im] : model.images) {
    const Eigen::Vector3d c = m.rotation * im.pose.C();
    lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
  }
  if (!model.points3D.empty())
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<double> v;
      v.reserve(model.points3D.size());
      for (const auto& [id, p] : model.points3D) v.push_back(m.rotation.row(axis).dot(p.xyz));
      lo[axis] = std::min(lo[axis], Percentile(v, 0.02));
      hi[axis] = std::max(hi[axis], Percentile(v, 0.98));
    }
  m.centre = m.rotation.transpose() * ((lo + hi) / 2);
  const double radius = (hi - lo).norm() / 2;
  m.scale = radius > 1e-12 ? 1.0 / radius : 1.0;
  m.offset = Eigen::Vector3d(kModelSpacing * index, 0.0, 0.0);

  std::vector<Eigen::Vector3d> centres;
  for (const auto& [id, im] : model.images) centres.push_back(im.pose.C());
  m.frustum_depth = std::clamp(options.frustum_fraction * MedianNearestDistance(centres) * m.scale, 0.03, 0.15);

  const std::map<uint32_t, double> residuals = ImageResiduals(model);
  for (const auto& [id, im] : model.images) {
    ModelView3d::Camera c;
    c.name = im.name;
    c.model = index;
    const auto r = residuals.find(id);
    c.residual_px = r == residuals.end() ? std::nan("") : r->second;
    c.centre = m.ToView(im.pose.C());
    const std::array<Eigen::Vector2d, 4> rays = CornerRays(model.CameraOf(im));
    const Eigen::Matrix3d to_view = m.rotation * im.pose.R().transpose();
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d dir = to_view * Eigen::Vector3d(rays[k].x(), rays[k].y(), 1.0);
      c.corners[k] = c.centre + m.frustum_depth * dir;
    }
    view->cameras.push_back(c);
  }
  size_t k = 0;
  for (const auto& [id, p] : model.points3D) {
    if (k++ % point_step != 0) continue;
    view->points.push_back(m.ToView(p.xyz));
    view->colours.push_back(p.color);
  }
  view->models.push_back(m);
}

// A number of `unit`s, as the JSON's integer.
long long Units(double v, double unit) {
  const double q = std::round(v / unit);
  return std::isfinite(q) ? static_cast<long long>(std::clamp(q, -1e15, 1e15)) : 0;
}

// `s` as a JSON string with "<" escaped (no "</script" can end the element holding it); an
// invalid UTF-8 byte becomes U+FFFD.
std::string JsonString(const std::string& s) {
  const std::string dumped = nlohmann::json(s).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  std::string out;
  for (char ch : dumped) {
    if (ch == '<')
      out += "\\u003c";
    else
      out += ch;
  }
  return out;
}

std::string ResidualGradient() {
  std::string g = "linear-gradient(to right";
  for (const char* c : kResidualColours) g += std::string(",") + c;
  return g + ")";
}

}  // namespace

ModelView3d MakeModelView3d(const std::vector<const Reconstruction*>& models, const ModelView3dOptions& options) {
  ModelView3d view;
  std::vector<const Reconstruction*> shown;
  for (const Reconstruction* m : models)
    if (m && !m->images.empty()) shown.push_back(m), view.points_total += m->points3D.size();
  const size_t max_points = std::max<size_t>(options.max_points, 1);
  view.point_step = view.points_total > max_points ? (view.points_total + max_points - 1) / max_points : 1;
  for (size_t i = 0; i < shown.size(); ++i) AddModel(*shown[i], static_cast<int>(i), view.point_step, options, &view);
  // COLMAP's default grey everywhere: no colour of their own.
  const Eigen::Matrix<uint8_t, 3, 1> grey = Point3D().color;
  if (std::all_of(view.colours.begin(), view.colours.end(), [&](const auto& c) { return c == grey; }))
    view.colours.clear();
  for (const ModelView3d::Camera& c : view.cameras)
    if (std::isfinite(c.residual_px)) view.residual_scale_px = std::max(view.residual_scale_px, c.residual_px);
  return view;
}

std::string ModelView3dJson(const ModelView3d& view) {
  std::ostringstream j;
  j << "{\"camera_unit\":" << FormatNumber("%g", kCameraUnit) << ",\"point_unit\":" << FormatNumber("%g", kPointUnit)
    << ",\"models\":[";
  for (size_t i = 0; i < view.models.size(); ++i) {
    const ModelView3d::Model& m = view.models[i];
    j << (i ? "," : "") << "{\"images\":" << m.images << ",\"points\":" << m.points << ",\"offset\":["
      << FormatNumber("%.4f", m.offset.x()) << "," << FormatNumber("%.4f", m.offset.y()) << ","
      << FormatNumber("%.4f", m.offset.z()) << "],\"colour\":\"" << ModelColour(static_cast<int>(i)) << "\"}";
  }
  j << "],\"residual_scale\":" << FormatNumber("%.3f", view.residual_scale_px) << ",\"residual_colours\":[";
  for (size_t i = 0; i < std::size(kResidualColours); ++i) j << (i ? ",\"" : "\"") << kResidualColours[i] << "\"";
  j << "],\"no_residual_colour\":\"" << kNoResidualColour << "\",\"cameras\":[";
  for (size_t i = 0; i < view.cameras.size(); ++i) {
    const ModelView3d::Camera& c = view.cameras[i];
    j << (i ? ",\n" : "\n") << "{\"name\":" << JsonString(c.name) << ",\"model\":" << c.model << ",\"residual\":"
      << (std::isnan(c.residual_px) ? std::string("null") : FormatNumber("%.3f", std::min(c.residual_px, 1e6))) << ",\"frustum\":[";
    const auto put = [&](const Eigen::Vector3d& v, bool first) {
      j << (first ? "" : ",") << Units(v.x(), kCameraUnit) << "," << Units(v.y(), kCameraUnit) << ","
        << Units(v.z(), kCameraUnit);
    };
    put(c.centre, true);
    for (const Eigen::Vector3d& corner : c.corners) put(corner, false);
    j << "]}";
  }
  j << "],\n\"points\":[";
  for (size_t i = 0; i < view.points.size(); ++i) {
    const Eigen::Vector3d& p = view.points[i];
    j << (i ? "," : "") << Units(p.x(), kPointUnit) << "," << Units(p.y(), kPointUnit) << "," << Units(p.z(), kPointUnit);
    if (i % 64 == 63) j << "\n";
  }
  j << "]";
  if (!view.colours.empty()) {
    static const char kHex[] = "0123456789abcdef";
    std::string hex;
    hex.reserve(6 * view.colours.size());
    for (const auto& c : view.colours)
      for (int k = 0; k < 3; ++k) hex += kHex[c[k] >> 4], hex += kHex[c[k] & 15];
    j << ",\n\"colours\":\"" << hex << "\"";
  }
  j << "}";
  return j.str();
}

std::string ModelView3dSection(const ModelView3d& view) {
  std::ostringstream h;
  h << "<h2>3D view</h2>\n";
  if (view.cameras.empty()) {
    h << "<p>No image was registered: no camera and no point to show.</p>\n";
    return h.str();
  }
  const bool several = view.models.size() > 1;
  h << "<p>" << view.cameras.size() << " cameras as frusta (each pointing where its image looks) and "
    << view.points.size() << " points" << (several ? " of the " + std::to_string(view.models.size()) + " models" : "")
    << ". Drag to rotate about the model's centre, scroll to zoom, right-drag "
       "to pan; hover a camera for its image.";
  if (view.point_step > 1)
    h << " Of the " << view.points_total << " points, one in " << view.point_step
      << " (in id order) is shown, to keep the page small.";
  if (several)
    h << " The " << view.models.size() << " models have no frame in common: each is shown in its own scale "
         "and orientation, side by side from the largest (left).";
  h << "</p>\n";
  if (several) {
    h << "<p>Cameras coloured by <label><input type=\"radio\" name=\"pgba-view3d-colour\" value=\"model\" checked> "
         "model</label> <label><input type=\"radio\" name=\"pgba-view3d-colour\" value=\"residual\"> median "
         "reprojection error of the image</label></p>\n";
  }
  h << "<p id=\"pgba-view3d-legend-residual\"" << (several ? " style=\"display:none\"" : "")
    << ">Median reprojection error of the image's observations: 0 px <span style=\"display:inline-block;width:240px;height:12px;"
       "vertical-align:middle;background:"
    << ResidualGradient() << "\"></span> " << FormatNumber("%.2f", view.residual_scale_px)
    << " px and more; grey: the image observes no point.</p>\n";
  if (several) {
    h << "<p id=\"pgba-view3d-legend-model\">";
    for (size_t i = 0; i < view.models.size(); ++i)
      h << (i ? " &nbsp; " : "") << "<span style=\"color:" << ModelColour(static_cast<int>(i)) << "\">&#9632;</span> model "
        << i << " (" << view.models[i].images << " images)";
    h << "</p>\n";
  }
  h << "<div id=\"pgba-view3d\" style=\"position:relative;width:100%;height:560px;border:1px solid #444\">"
       "<noscript><p>The 3D view needs JavaScript.</p></noscript></div>\n"
    << "<script type=\"application/json\" id=\"pgba-view3d-data\">" << ModelView3dJson(view) << "</script>\n";
  return h.str();
}

std::string ModelView3dScripts(const ModelView3d& view) {
  if (view.cameras.empty()) return "";
  std::string s;
  for (std::string_view script : {ThreeJsScript(), OrbitControlsScript(), ModelView3dScript()})
    s.append("<script>\n").append(script).append("\n</script>\n");
  return s;
}

}  // namespace pgba
