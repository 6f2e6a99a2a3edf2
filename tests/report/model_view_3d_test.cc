// The 3D view of report.html: each frustum's apex is its camera's centre and its corners lie on
// the rays of the image's corners, at a depth set by the distance to the nearest camera; each
// image's residual is the median reprojection error of its observations; the view's up is the
// cameras' up (held upright) or the opposite of their viewing direction (looking down on a flat
// scene); several models sit side by side without overlapping; points above the limit are
// thinned to every k-th; the page's JSON parses, carries what the view holds at its fixed
// precision and cannot end its <script> element; the scripts embedded at build time fit in one.
#include "report/model_view_3d.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <nlohmann/json.hpp>

#include "report/embedded_scripts.h"
#include "report/html_report.h"

namespace pgba {
namespace {

constexpr int kWidth = 640, kHeight = 480;

Camera PinholeCamera() {
  Camera c;
  c.camera_id = 1;
  c.model = CameraModel::kPinhole;
  c.width = kWidth;
  c.height = kHeight;
  c.params = {500.0, 500.0, 320.0, 240.0};
  return c;
}

// The pose of a camera at `centre` looking along `look` with the image's up along `up`.
Pose LookAt(const Eigen::Vector3d& centre, const Eigen::Vector3d& look, const Eigen::Vector3d& up) {
  const Eigen::Vector3d z = look.normalized(), x = z.cross(up).normalized(), y = z.cross(x);
  Eigen::Matrix3d R;  // rows: the camera's axes in the world (image y down)
  R.row(0) = x.transpose();
  R.row(1) = y.transpose();
  R.row(2) = z.transpose();
  return Pose::FromRC(R, centre);
}

void AddImage(Reconstruction* model, uint32_t id, const Pose& pose) {
  Image im;
  im.image_id = id;
  im.name = "img_" + std::to_string(id) + ".png";
  im.camera_id = 1;
  im.pose = pose;
  model->images[id] = im;
}

// Adds a point seen by every image that has it in front, each observation displaced from its
// exact projection by `offset(image_id)` pixels.
template <typename Offset>
void AddPoint(Reconstruction* model, const Eigen::Vector3d& X, Offset offset) {
  std::vector<TrackElement> track;
  for (auto& [id, im] : model->images) {
    const Eigen::Vector3d x_cam = im.pose.ToCamera(X);
    if (x_cam.z() <= 0) continue;
    Point2D p;
    p.xy = model->CameraOf(im).Project(x_cam) + offset(id);
    im.points2D.push_back(p);
    track.push_back({id, static_cast<uint32_t>(im.points2D.size() - 1)});
  }
  model->AddPoint3D(X, track);
}

// A ring of `n` cameras of radius 4 about the origin, upright for the world's +z, looking at
// the centre, and a grid of points on a box about it.
Reconstruction Ring(int n, double scale = 1.0) {
  Reconstruction model;
  model.cameras[1] = PinholeCamera();
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    const Eigen::Vector3d c = scale * Eigen::Vector3d(4 * std::cos(a), 4 * std::sin(a), 0.5);
    AddImage(&model, i + 1, LookAt(c, -c, Eigen::Vector3d::UnitZ()));
  }
  for (int x = -2; x <= 2; ++x)
    for (int y = -2; y <= 2; ++y)
      for (int z = -1; z <= 1; ++z)
        AddPoint(&model, scale * Eigen::Vector3d(0.4 * x, 0.4 * y, 0.5 * z), [](uint32_t) { return Eigen::Vector2d::Zero(); });
  return model;
}

// The view frame's point in the model's world frame.
Eigen::Vector3d ToWorld(const ModelView3d::Model& m, const Eigen::Vector3d& v) {
  return m.rotation.transpose() * ((v - m.offset) / m.scale) + m.centre;
}

TEST(ModelView3d, FrustaStartAtTheCameraAndSpanTheImagesCorners) {
  const Reconstruction model = Ring(40);
  const ModelView3d view = MakeModelView3d({&model});
  ASSERT_EQ(view.models.size(), 1u);
  ASSERT_EQ(view.cameras.size(), 40u);
  const ModelView3d::Model& m = view.models[0];
  EXPECT_NEAR((m.rotation * m.rotation.transpose() - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(m.rotation.determinant(), 1.0, 1e-12) << "a mirrored view";
  // Neighbours on the ring: 2 * 4 * sin(pi / 40) apart; half that deep (view units).
  const double nearest = 8 * std::sin(M_PI / 40);
  ASSERT_GT(0.5 * nearest * m.scale, 0.03);
  ASSERT_LT(0.5 * nearest * m.scale, 0.15);
  EXPECT_NEAR(m.frustum_depth, 0.5 * nearest * m.scale, 1e-12);
  // Sparse cameras: no deeper than 0.15 of the model's radius.
  const Reconstruction sparse = Ring(5);
  EXPECT_EQ(MakeModelView3d({&sparse}).models[0].frustum_depth, 0.15);
  const Eigen::Vector2d corners[4] = {{0, 0}, {kWidth, 0}, {kWidth, kHeight}, {0, kHeight}};
  size_t k = 0;
  for (const auto& [id, im] : model.images) {
    const ModelView3d::Camera& c = view.cameras[k++];
    EXPECT_EQ(c.name, im.name);
    EXPECT_NEAR((ToWorld(m, c.centre) - im.pose.C()).norm(), 0.0, 1e-9);
    for (int i = 0; i < 4; ++i) {
      const Eigen::Vector3d x_cam = im.pose.ToCamera(ToWorld(m, c.corners[i]));
      EXPECT_NEAR(x_cam.z(), m.frustum_depth / m.scale, 1e-9) << "corner " << i;
      EXPECT_NEAR((model.CameraOf(im).Project(x_cam) - corners[i]).norm(), 0.0, 1e-6) << "corner " << i;
    }
  }
  // Centred and of radius 1: every camera within it.
  for (const ModelView3d::Camera& c : view.cameras) EXPECT_LE(c.centre.norm(), 1.0 + 1e-9);
}

TEST(ModelView3d, UpIsTheCamerasUpOrAboveTheFlatSceneTheyLookDownOn) {
  // Upright cameras about an object: their up, the world's +z.
  const Reconstruction ring = Ring(8);
  EXPECT_GT(MakeModelView3d({&ring}).models[0].rotation.row(1).dot(Eigen::Vector3d::UnitZ()), 0.99);

  // An aerial block: cameras 10 above a flat ground, all looking straight down with the same
  // heading (their image's up is the world's +y, horizontal); the view's up is +z all the same.
  Reconstruction block;
  block.cameras[1] = PinholeCamera();
  uint32_t id = 1;
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 3; ++y)
      AddImage(&block, id++, LookAt({2.0 * x, 2.0 * y, 10.0}, -Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY()));
  for (int x = -4; x <= 10; ++x)
    for (int y = -4; y <= 8; ++y)
      AddPoint(&block, {1.0 * x, 1.0 * y, 0.05 * ((x * y) % 3)}, [](uint32_t) { return Eigen::Vector2d::Zero(); });
  const ModelView3d view = MakeModelView3d({&block});
  EXPECT_GT(view.models[0].rotation.row(1).dot(Eigen::Vector3d::UnitZ()), 0.99);
  for (const ModelView3d::Camera& c : view.cameras) EXPECT_GT(c.centre.y(), 0.0) << "a camera below the ground";
}

TEST(ModelView3d, AnImagesResidualIsTheMedianOfItsObservationsErrors) {
  Reconstruction model = Ring(4);
  // Image 1's observations displaced by 3-4-5 pixels, one of them by 1000 px; image 3's by 0.5.
  Reconstruction displaced;
  displaced.cameras = model.cameras;
  for (const auto& [id, im] : model.images) AddImage(&displaced, id, im.pose);
  int n = 0;
  for (const auto& [pid, p] : model.points3D)
    AddPoint(&displaced, p.xyz, [&](uint32_t image) {
      if (image == 1) return Eigen::Vector2d(n++ == 0 ? 1000.0 : 3.0, 4.0);
      return image == 3 ? Eigen::Vector2d(0.3, 0.4) : Eigen::Vector2d::Zero();
    });
  // Image 5 observes no point.
  AddImage(&displaced, 5, LookAt({0, 0, 9}, -Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY()));
  const ModelView3d view = MakeModelView3d({&displaced});
  ASSERT_EQ(view.cameras.size(), 5u);
  EXPECT_NEAR(view.cameras[0].residual_px, 5.0, 1e-6);
  EXPECT_NEAR(view.cameras[1].residual_px, 0.0, 1e-6);
  EXPECT_NEAR(view.cameras[2].residual_px, 0.5, 1e-6);
  EXPECT_TRUE(std::isnan(view.cameras[4].residual_px));
  EXPECT_NEAR(view.residual_scale_px, 5.0, 1e-6);
  // Under 1 px everywhere: the scale still runs to 1 px.
  EXPECT_EQ(MakeModelView3d({&model}).residual_scale_px, 1.0);

  const nlohmann::json j = nlohmann::json::parse(ModelView3dJson(view));
  EXPECT_EQ(j["cameras"][0]["residual"].get<double>(), 5.0);
  EXPECT_TRUE(j["cameras"][4]["residual"].is_null());
  EXPECT_EQ(j["residual_scale"].get<double>(), 5.0);
}

TEST(ModelView3d, SeveralModelsSideBySideEachOfRadiusOne) {
  const Reconstruction small = Ring(6), large = Ring(10, 100.0);
  const ModelView3d view = MakeModelView3d({&large, &small});
  ASSERT_EQ(view.models.size(), 2u);
  EXPECT_EQ(view.models[0].images, 10u);
  EXPECT_EQ(view.models[1].images, 6u);
  // Each model about its offset within a radius of 1 (cameras and the points of these scenes);
  // the two do not overlap.
  double right_of_first = -1e9, left_of_second = 1e9;
  for (const ModelView3d::Camera& c : view.cameras) {
    const ModelView3d::Model& m = view.models[c.model];
    EXPECT_LE((c.centre - m.offset).norm(), 1.0 + 1e-9);
    for (const Eigen::Vector3d& corner : c.corners)
      (c.model == 0 ? right_of_first : left_of_second) =
          c.model == 0 ? std::max(right_of_first, corner.x()) : std::min(left_of_second, corner.x());
  }
  EXPECT_EQ(view.cameras.front().model, 0);
  EXPECT_EQ(view.cameras.back().model, 1);
  EXPECT_LT(right_of_first, left_of_second);
  ASSERT_EQ(view.points.size(), large.points3D.size() + small.points3D.size());
  for (size_t i = 0; i < view.points.size(); ++i) {
    if (i < large.points3D.size())
      EXPECT_LT(view.points[i].x(), left_of_second);
    else
      EXPECT_GT(view.points[i].x(), right_of_first);
  }

  // The page says the models share no frame and offers both colourings, by model first.
  const std::string section = ModelView3dSection(view);
  EXPECT_NE(section.find("16 cameras as frusta"), std::string::npos);
  EXPECT_NE(section.find(std::to_string(view.points.size()) + " points of the 2 models"), std::string::npos);
  EXPECT_NE(section.find("The 2 models have no frame in common"), std::string::npos);
  EXPECT_NE(section.find("value=\"model\" checked"), std::string::npos);
  EXPECT_NE(section.find("id=\"pgba-view3d-legend-model\""), std::string::npos);
  // One model: coloured by residual, no switch.
  const std::string one = ModelView3dSection(MakeModelView3d({&small}));
  EXPECT_EQ(one.find("pgba-view3d-colour"), std::string::npos);
  EXPECT_EQ(one.find("no frame in common"), std::string::npos);
}

TEST(ModelView3d, PointsAboveTheLimitAreThinnedToEveryKthAndKeepTheirColours) {
  const Reconstruction model = Ring(5);  // 75 points, COLMAP's default grey
  ModelView3dOptions options;
  options.max_points = 20;
  ModelView3d view = MakeModelView3d({&model}, options);
  EXPECT_EQ(view.points_total, 75u);
  EXPECT_EQ(view.point_step, 4u);
  ASSERT_EQ(view.points.size(), 19u);  // ids 1, 5, 9, ..., 73
  const ModelView3d::Model& m = view.models[0];
  EXPECT_NEAR((ToWorld(m, view.points[1]) - std::next(model.points3D.begin(), 4)->second.xyz).norm(), 0.0, 1e-9);
  EXPECT_TRUE(view.colours.empty()) << "the default grey is no colour";
  EXPECT_NE(ModelView3dSection(view).find("Of the 75 points, one in 4 (in id order) is shown"), std::string::npos);
  EXPECT_EQ(nlohmann::json::parse(ModelView3dJson(view)).count("colours"), 0u);

  Reconstruction coloured = model;
  std::next(coloured.points3D.begin(), 4)->second.color << 255, 16, 0;
  view = MakeModelView3d({&coloured}, options);
  ASSERT_EQ(view.colours.size(), view.points.size());
  const std::string hex = nlohmann::json::parse(ModelView3dJson(view))["colours"];
  EXPECT_EQ(hex.size(), 6 * view.points.size());
  EXPECT_EQ(hex.substr(0, 12), "808080ff1000");
  // Within the limit: every point.
  EXPECT_EQ(MakeModelView3d({&model}).points.size(), 75u);
}

TEST(ModelView3d, TheJsonHoldsTheViewAtFixedPrecisionAndCannotEndItsScript) {
  Reconstruction model = Ring(3);
  model.images.at(2).name = "a</script><script>alert(1)</script>\xff.png";  // and not UTF-8
  const ModelView3d view = MakeModelView3d({&model});
  const std::string json = ModelView3dJson(view);
  EXPECT_EQ(json.find('<'), std::string::npos);
  EXPECT_EQ(json, ModelView3dJson(MakeModelView3d({&model}))) << "not deterministic";
  const nlohmann::json j = nlohmann::json::parse(json);
  ASSERT_EQ(j["cameras"].size(), 3u);
  EXPECT_EQ(j["cameras"][1]["name"].get<std::string>(), "a</script><script>alert(1)</script>\xef\xbf\xbd.png");
  const double cu = j["camera_unit"], pu = j["point_unit"];
  for (size_t i = 0; i < 3; ++i) {
    const nlohmann::json& f = j["cameras"][i]["frustum"];
    ASSERT_EQ(f.size(), 15u);
    const ModelView3d::Camera& c = view.cameras[i];
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(f[a].get<long long>(), std::llround(c.centre[a] / cu));
      EXPECT_EQ(f[3 + a].get<long long>(), std::llround(c.corners[0][a] / cu));
    }
  }
  ASSERT_EQ(j["points"].size(), 3 * view.points.size());
  EXPECT_EQ(j["points"][4].get<long long>(), std::llround(view.points[1].y() / pu));
  EXPECT_EQ(j["models"][0]["colour"], "#1f77b4");

  // The section holds the data in one JSON script; the scripts that draw it are three.
  const std::string section = ModelView3dSection(view);
  EXPECT_NE(section.find("<script type=\"application/json\" id=\"pgba-view3d-data\">" + json + "</script>"),
            std::string::npos);
  size_t scripts = 0;
  const std::string tail = ModelView3dScripts(view);
  for (size_t at = tail.find("</script>"); at != std::string::npos; at = tail.find("</script>", at + 1)) ++scripts;
  EXPECT_EQ(scripts, 3u);
  EXPECT_EQ(tail.find("<script src"), std::string::npos);
}

TEST(ModelView3d, WithoutACameraTheSectionSaysSoAndNoScriptIsAdded) {
  const Reconstruction empty;
  const ModelView3d view = MakeModelView3d({&empty, nullptr});
  EXPECT_TRUE(view.cameras.empty());
  const std::string section = ModelView3dSection(view);
  EXPECT_NE(section.find("No image was registered"), std::string::npos);
  EXPECT_EQ(section.find("<script"), std::string::npos);
  EXPECT_EQ(ModelView3dScripts(view), "");

  // report.html: the 3D view after the summary, before the top view; none without a model.
  const Reconstruction ring = Ring(4);
  HtmlReportInput in;
  in.title = "t";
  in.model = &ring;
  const std::string html = RunReportHtml(in);
  const size_t view3d = html.find("<h2>3D view</h2>"), top = html.find("<h2>Top view</h2>");
  ASSERT_NE(view3d, std::string::npos);
  EXPECT_LT(html.find("<h2>Summary</h2>"), view3d);
  EXPECT_LT(view3d, top);
  EXPECT_NE(html.find("id=\"pgba-view3d-data\""), std::string::npos);
  in.model = nullptr;
  EXPECT_EQ(RunReportHtml(in).find("3D view"), std::string::npos);
  EXPECT_EQ(RunReportHtml(in).find("<script"), std::string::npos);
}

TEST(EmbeddedScripts, ThreeJsItsControlsAndTheViewEachFitInAScriptElement) {
  EXPECT_NE(ThreeJsScript().find("WebGLRenderer"), std::string_view::npos);
  EXPECT_NE(OrbitControlsScript().find("OrbitControls"), std::string_view::npos);
  EXPECT_NE(ModelView3dScript().find("pgba-view3d-data"), std::string_view::npos);
  for (std::string_view script : {ThreeJsScript(), OrbitControlsScript(), ModelView3dScript()}) {
    std::string lower(script);
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
    EXPECT_EQ(lower.find("</script"), std::string::npos);
  }
}

}  // namespace
}  // namespace pgba
