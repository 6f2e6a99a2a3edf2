#include "report/html_report.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "pgba/optim/intrinsics.h"
#include "pgba/scene/camera.h"
#include "pgba/util/text_format.h"
#include "report/model_view_3d.h"
#include "report/svg_plot.h"

namespace pgba {
namespace {

// ", sample of N of M tracks" when the convergence curve covers only some of the tracks
// (mapper/convergence_curve.h), "" otherwise.
std::string ConvergenceSampleNote(const HtmlReportInput& in) {
  if (in.convergence_tracks == 0 || in.convergence_tracks >= in.convergence_tracks_total) return "";
  return ", sample of " + std::to_string(in.convergence_tracks) + " of " + std::to_string(in.convergence_tracks_total) +
         " tracks";
}

void Row(std::ostringstream& h, const std::string& key, const std::string& value) {
  h << "<tr><th>" << XmlEscape(key) << "</th><td>" << XmlEscape(value) << "</td></tr>\n";
}

// A camera parameter's value: pixels (focal, principal point) to 0.01 px, the distortion
// coefficients to 4 significant digits.
std::string ParamValue(const std::string& name, double v) {
  const bool pixels = !name.empty() && (name[0] == 'f' || name[0] == 'c');
  return FormatNumber(pixels ? "%.2f" : "%.4g", v);
}

double NumberAt(const nlohmann::json& array, size_t i, double fallback) {
  return array.is_array() && i < array.size() && array[i].is_number() ? array[i].get<double>() : fallback;
}

// Each camera's parameters by name: the value the run began from (the calibration file's, the
// EXIF focal or the default guess: "prior_params", else the pointless BA's start), the final
// value and its standard deviation; a parameter not estimated says so.
void IntrinsicsTable(std::ostringstream& h, const nlohmann::json& intrinsics) {
  h << "<h2>Camera parameters</h2><p>Estimated by the self-calibration: the value the run began from, the final "
       "value and its standard deviation (pixels for f, cx, cy; no unit for the distortion).</p>\n"
       "<table><tr><th>camera</th><th>model</th><th>parameter</th><th>start of the run</th><th>final</th>"
       "<th>standard deviation</th></tr>\n";
  for (const auto& camera : intrinsics) {
    CameraModel model = CameraModel::kPinhole;
    const bool known = ParseCameraModel(camera.value("model", ""), &model);
    const nlohmann::json estimated = camera.value("params", nlohmann::json::array());
    const nlohmann::json final_params = camera.value("final_params", nlohmann::json::array());
    const nlohmann::json prior = camera.value("prior_params", nlohmann::json::array());
    const int n = known ? CameraModelNumParams(model) : static_cast<int>(estimated.size());
    for (int i = 0; i < n; ++i) {
      const nlohmann::json* p = nullptr;
      for (const auto& e : estimated)
        if (e.value("index", -1) == i) p = &e;
      if (!known && i < static_cast<int>(estimated.size())) p = &estimated[i];
      const std::string name = known ? IntrinsicParamName(model, i) : p->value("name", "?");
      const auto number = [](const nlohmann::json* q, const char* key) {
        return q && q->contains(key) && (*q)[key].is_number() ? (*q)[key].get<double>() : NAN;
      };
      const double final_value = NumberAt(final_params, i, number(p, "final"));
      const double start = NumberAt(prior, i, p ? number(p, "initial") : final_value);
      const double sd = number(p, "stddev");
      const auto cell = [&](double v) { return std::isfinite(v) ? ParamValue(name, v) : std::string("-"); };
      h << "<tr><td>" << camera.value("camera_id", 0) << "</td><td>" << XmlEscape(camera.value("model", ""))
        << "</td><td>" << XmlEscape(p ? p->value("name", name) : name) << "</td><td class=\"n\">" << cell(start)
        << "</td><td class=\"n\">" << cell(final_value) << "</td><td class=\"n\">"
        << (p ? (std::isfinite(sd) ? FormatNumber("%.2g", sd) : std::string("-"))
              // Estimated by an earlier pass only (a run that matched again): not held throughout.
              : (ParamValue(name, start) == ParamValue(name, final_value) ? std::string("held")
                                                                          : std::string("held in the last pass")))
        << "</td></tr>\n";
    }
  }
  h << "</table>\n";
}

// The per-image verification record: top-level "image_verification" or the verification
// stage's "images" (one entry per image not verified as it was: reregistered or dropped).
nlohmann::json VerificationRecords(const nlohmann::json& r) {
  if (r.contains("image_verification") && r["image_verification"].is_array()) return r["image_verification"];
  if (r.contains("stages") && r["stages"].contains("verification"))
    return r["stages"]["verification"].value("images", nlohmann::json::array());
  return nlohmann::json::array();
}

// The images left out and why (report.json's "images_dropped_reason", else the verification
// record's reason, else the names alone), and the images registered again after a failed check.
void DroppedImagesTable(std::ostringstream& h, const nlohmann::json& r) {
  const nlohmann::json verification = VerificationRecords(r);
  std::vector<std::pair<std::string, std::string>> dropped, again;
  for (const auto& v : verification)
    if (v.is_object() && v.value("status", "") == "reregistered")
      again.push_back({v.value("image", "?"), v.value("reason", "")});
  if (r.contains("images_dropped") && r["images_dropped"].is_array()) {
    const nlohmann::json reasons = r.value("images_dropped_reason", nlohmann::json::object());
    for (const auto& n : r["images_dropped"]) {
      const std::string name = n.get<std::string>();
      std::string reason = reasons.value(name, "");
      for (const auto& v : verification)
        if (reason.empty() && v.is_object() && v.value("image", "") == name && v.value("status", "") == "dropped")
          reason = "dropped by the final check: " + v.value("reason", "");
      dropped.push_back({name, reason});
    }
  } else {
    for (const auto& v : verification)
      if (v.is_object() && v.value("status", "") == "dropped")
        dropped.push_back({v.value("image", "?"), "dropped by the final check: " + v.value("reason", "")});
  }
  const auto table = [&h](const char* title, const std::vector<std::pair<std::string, std::string>>& rows) {
    if (rows.empty()) return;
    h << "<h2>" << title << "</h2><table><tr><th>image</th><th>reason</th></tr>\n";
    for (const auto& [name, reason] : rows)
      h << "<tr><td>" << XmlEscape(name) << "</td><td>" << XmlEscape(reason) << "</td></tr>\n";
    h << "</table>\n";
  };
  table("Images not registered", dropped);
  table("Images registered again after failing the final check", again);
}

std::vector<std::string> StagesInOrder(const nlohmann::json& stages) {
  std::vector<std::pair<size_t, std::string>> order;
  for (const auto& [name, st] : stages.items()) order.push_back({st.value("order", size_t{0}), name});
  std::sort(order.begin(), order.end());
  std::vector<std::string> names;
  for (const auto& [o, name] : order) names.push_back(name);
  return names;
}

// What a stage of report.json does, in a user's words ("" for a stage not listed).
std::string StageDescription(const std::string& name) {
  static const std::map<std::string, std::string> kWords = {
      {"features", "SIFT features of every image"},
      {"match", "feature matching and geometric verification of image pairs; tracks"},
      {"first_pass", "a reconstruction with the starting calibration, whose cameras the matching then uses"},
      {"match_recalibrated", "matching again with the self-calibrated cameras"},
      {"pairs", "view graph: the relative pose of every image pair sharing tracks"},
      {"focal_estimation", "focal lengths from the image pairs"},
      {"pairs_recalibrated", "view graph again, with the estimated focal lengths"},
      {"triplets", "image triplets, each solved by its own bundle adjustment"},
      {"global_init", "initial poses: rotation and translation averaging"},
      {"gcp_alignment", "initial poses moved into the frame of the ground control points"},
      {"workspace", "reading the workspace"},
      {"local_hessians", "local bundle adjustments and their Hessians"},
      {"global_ba", "pointless global bundle adjustment: the final poses"},
      {"gcp_check", "ground control points triangulated with the final poses"},
      {"convergence", "reprojection error per iteration (the convergence plot)"},
      {"verification", "every registered image checked against its observations and verified pairs"},
      {"triangulation", "points triangulated with the final poses"},
      {"more_models", "the other models (components of the view graph), each adjusted on its own"},
      {"components", "images left out joined by absolute pose; models merged by the points or verified pairs they share"},
      {"output", "writing sparse/ and points.ply"},
      {"evaluation", "reprojection error of the result (and errors against the ground truth)"}};
  // A stage done again keeps its first round under a suffix saying why.
  for (const auto& [suffix, why] : {std::pair<std::string, std::string>{"_before_readjustment",
                                                                        "done again without the images the verification dropped"},
                                    {"_before_joining", "done again with the images joined by absolute pose"},
                                    {"_before_triplet_start",
                                     "its first step raised the reprojection error: done again from the image "
                                     "triplets' own adjustment"}})
    if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
      const std::string first = StageDescription(name.substr(0, name.size() - suffix.size()));
      return first.empty() ? "first round, " + why : first + " (first round, " + why + ")";
    }
  const auto it = kWords.find(name);
  return it == kWords.end() ? "" : it->second;
}

// Every stage in the order it ran with its seconds, and their total beside the run's own time;
// a stage holding stages (a first pass run again) lists them under it, outside the total.
void StagesTable(std::ostringstream& h, const nlohmann::json& r) {
  double total = 0.0;
  h << "<h2>Stages</h2><table><tr><th>stage</th><th>seconds</th><th>peak memory (MiB)</th><th>what it does</th></tr>\n";
  for (const std::string& name : StagesInOrder(r["stages"])) {
    const nlohmann::json& st = r["stages"][name];
    const double s = st.value("seconds", 0.0);
    total += s;
    h << "<tr><td>" << XmlEscape(name) << "</td><td class=\"n\">" << FormatNumber("%.2f", s)
      << "</td><td class=\"n\">" << FormatNumber("%.0f", st.value("peak_rss_mb", 0.0)) << "</td><td>"
      << XmlEscape(StageDescription(name)) << "</td></tr>\n";
    if (st.contains("stages") && st["stages"].is_object())
      for (const std::string& inner : StagesInOrder(st["stages"]))
        h << "<tr style=\"color:#777\"><td>&nbsp;&nbsp;" << XmlEscape(name + " / " + inner) << "</td><td class=\"n\">"
          << FormatNumber("%.2f", st["stages"][inner].value("seconds", 0.0)) << "</td><td></td><td></td></tr>\n";
  }
  h << "<tr><th>total</th><th class=\"n\">" << FormatNumber("%.2f", total) << "</th><th></th><th></th></tr>\n";
  if (r.contains("seconds") && r["seconds"].is_number())
    h << "<tr><th>whole run</th><th class=\"n\">" << FormatNumber("%.2f", r["seconds"].get<double>())
      << "</th><th></th><th>from the start of the command to its report</th></tr>\n";
  h << "</table>\n";
}

// Why the passes ended (GlobalBASummary::stop_reason), in words with the config key that sets it.
std::string StopReasonText(const std::string& reason) {
  if (reason == "cost_tolerance")
    return "the last pass lowered the reprojection cost by less than global_ba.relinearize_cost_tolerance";
  if (reason == "step_tolerance")
    return "the last pass moved the local models by less than global_ba.relinearize_tolerance noise sigmas";
  if (reason == "refused_step") return "a further pass raised the reprojection cost; the last kept pass is the result";
  if (reason == "max_relinearizations") return "global_ba.max_relinearizations passes reached";
  if (reason == "misfit_below_threshold") return "the local models agreed with each other: one pass was enough";
  if (reason == "no_relinearization") return "one pass (global_ba.max_relinearizations is 0)";
  return reason;
}

// A column of the passes' table (GlobalBASummary::Pass in report.json) in words.
std::string PassColumnName(const std::string& key) {
  if (key == "robust_cost") return "reprojection cost (robust, px²)";
  if (key == "outlier_px") return "outlier threshold (px)";
  if (key == "displacement_sigmas") return "largest move of a local model (noise sigmas)";
  return key;
}

// The pointless global BA's passes (stages.global_ba.passes: one record per pass, its cost
// first) and whether it converged, where the run recorded them.
void GlobalBaPasses(std::ostringstream& h, const nlohmann::json& r) {
  if (!r.contains("stages") || !r["stages"].contains("global_ba")) return;
  const nlohmann::json& ba = r["stages"]["global_ba"];
  const nlohmann::json passes = ba.value("passes", nlohmann::json::array());
  if (!ba.contains("converged") && (!passes.is_array() || passes.empty())) return;
  h << "<h2>Global bundle adjustment</h2>\n";
  if (ba.contains("converged") && ba["converged"].is_boolean()) {
    const std::string stop = ba.value("stop_reason", "");
    h << "<p>" << (ba["converged"].get<bool>()
                       ? "Converged" + (stop.empty() ? std::string(".") : ": " + XmlEscape(StopReasonText(stop)) + ".")
                       : "<b>Did not converge</b>" +
                             (stop.empty() ? std::string() : " (" + XmlEscape(StopReasonText(stop)) + ")") +
                             ": the poses are usable but not final; a run with more iterations "
                             "(global_ba section of the config) may still improve them.")
      << "</p>\n";
  }
  if (!passes.is_array() || passes.empty()) return;
  std::vector<std::string> keys;  // every numeric key of any pass, "cost" first
  for (const auto& pass : passes)
    if (pass.is_object())
      for (const auto& [key, value] : pass.items())
        if ((value.is_number() || value.is_boolean()) && std::find(keys.begin(), keys.end(), key) == keys.end())
          keys.push_back(key);
  std::stable_partition(keys.begin(), keys.end(), [](const std::string& k) { return k.find("cost") != std::string::npos; });
  h << "<p>Each pass takes the local bundle adjustments' Hessians again where the previous one left the poses "
       "and solves again; a pass is kept when it lowers the reprojection cost. A last step that moved no "
       "image by more than global_ba.relinearize_tolerance of its noise is kept without taking them again "
       "(its cost: -).</p>\n";
  h << "<table><tr><th>pass</th>";
  for (const std::string& k : keys) h << "<th>" << XmlEscape(PassColumnName(k)) << "</th>";
  h << "</tr>\n";
  for (size_t i = 0; i < passes.size(); ++i) {
    h << "<tr><td>" << i + 1 << "</td>";
    for (const std::string& k : keys) {
      const nlohmann::json v = passes[i].is_object() ? passes[i].value(k, nlohmann::json()) : nlohmann::json();
      h << "<td class=\"n\">"
        << (v.is_boolean() ? std::string(v.get<bool>() ? "yes" : "no")
                           : v.is_number() ? FormatNumber("%.6g", v.get<double>()) : std::string("-"))
        << "</td>";
    }
    h << "</tr>\n";
  }
  h << "</table>\n";
}

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

}  // namespace

std::string TopViewSvg(const Reconstruction& model, int width, int height) {
  std::vector<Eigen::Vector3d> cams, pts;
  for (const auto& [id, im] : model.images) cams.push_back(im.pose.C());
  for (const auto& [id, p] : model.points3D) pts.push_back(p.xyz);
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
      << "\"><rect width=\"100%\" height=\"100%\" fill=\"white\" stroke=\"#444\"/>\n";
  if (cams.empty()) return svg.str() + "</svg>\n";
  // Principal axes of cameras and points together (cameras weighted up so that a few
  // cameras over many points still set the view).
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& c : cams) mean += c;
  mean /= cams.size();
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  const double wc = pts.empty() ? 1.0 : static_cast<double>(pts.size()) / cams.size();
  for (const auto& c : cams) cov += wc * (c - mean) * (c - mean).transpose();
  for (const auto& p : pts) cov += (p - mean) * (p - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Eigen::Vector3d a = eig.eigenvectors().col(2), b = eig.eigenvectors().col(1);
  auto project = [&](const Eigen::Vector3d& X) { return Eigen::Vector2d((X - mean).dot(a), (X - mean).dot(b)); };
  std::vector<double> xs, ys;
  for (const auto& c : cams) xs.push_back(project(c).x()), ys.push_back(project(c).y());
  std::vector<double> pxs, pys;
  for (const auto& p : pts) pxs.push_back(project(p).x()), pys.push_back(project(p).y());
  double xmin = *std::min_element(xs.begin(), xs.end()), xmax = *std::max_element(xs.begin(), xs.end());
  double ymin = *std::min_element(ys.begin(), ys.end()), ymax = *std::max_element(ys.begin(), ys.end());
  if (!pts.empty()) {
    xmin = std::min(xmin, Percentile(pxs, 0.02)), xmax = std::max(xmax, Percentile(pxs, 0.98));
    ymin = std::min(ymin, Percentile(pys, 0.02)), ymax = std::max(ymax, Percentile(pys, 0.98));
  }
  const double span = std::max({xmax - xmin, ymax - ymin, 1e-9});
  const double scale = std::min((width - 40) / std::max(xmax - xmin, 1e-9 * span),
                                (height - 40) / std::max(ymax - ymin, 1e-9 * span));
  auto sx = [&](double x) { return width / 2.0 + (x - (xmin + xmax) / 2) * scale; };
  auto sy = [&](double y) { return height / 2.0 - (y - (ymin + ymax) / 2) * scale; };
  // At most ~20k points drawn (every k-th), to keep the page small.
  const size_t step = std::max<size_t>(1, pts.size() / 20000);
  for (size_t i = 0; i < pts.size(); i += step) {
    if (pxs[i] < xmin || pxs[i] > xmax || pys[i] < ymin || pys[i] > ymax) continue;
    svg << "<circle cx=\"" << FormatNumber("%.1f", sx(pxs[i])) << "\" cy=\"" << FormatNumber("%.1f", sy(pys[i]))
        << "\" r=\"0.8\" fill=\"#888\"/>";
  }
  svg << "\n";
  size_t k = 0;
  for (const auto& [id, im] : model.images) {
    const Eigen::Vector3d dir = im.pose.R().row(2).transpose();  // viewing direction
    const Eigen::Vector2d c = project(im.pose.C());
    const Eigen::Vector2d d(dir.dot(a), dir.dot(b));
    svg << "<line x1=\"" << FormatNumber("%.1f", sx(c.x())) << "\" y1=\"" << FormatNumber("%.1f", sy(c.y())) << "\" x2=\""
        << FormatNumber("%.1f", sx(c.x()) + 12 * d.x()) << "\" y2=\"" << FormatNumber("%.1f", sy(c.y()) - 12 * d.y())
        << "\" stroke=\"#d62728\"/><circle cx=\"" << FormatNumber("%.1f", sx(c.x())) << "\" cy=\"" << FormatNumber("%.1f", sy(c.y()))
        << "\" r=\"3\" fill=\"#d62728\"><title>" << XmlEscape(im.name) << "</title></circle>\n";
    ++k;
  }
  svg << "</svg>\n";
  return svg.str();
}

std::string RunReportHtml(const HtmlReportInput& in) {
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" << XmlEscape(in.title) << "</title>\n"
    << "<style>body{font-family:sans-serif;margin:2em;max-width:1000px}table{border-collapse:collapse;margin:1em 0}"
       "th,td{border:1px solid #ccc;padding:4px 10px;text-align:left}th{background:#f4f4f4}"
       "td.n{text-align:right}h2{margin-top:1.5em}</style></head><body>\n"
    << "<h1>" << XmlEscape(in.title) << "</h1>\n";
  const nlohmann::json& r = in.report ? *in.report : nlohmann::json::object();

  h << "<h2>Summary</h2><table>\n";
  if (r.contains("images_input") && r.contains("images_registered"))
    Row(h, "images registered", std::to_string(r["images_registered"].get<long>()) + " / " +
                                    std::to_string(r["images_input"].get<long>()));
  if (r.contains("stages") && r["stages"].contains("features")) {
    const nlohmann::json& f = r["stages"]["features"];
    if (f.contains("features_mean")) Row(h, "features per image (mean)", FormatNumber("%.0f", f["features_mean"].get<double>()));
    const nlohmann::json adapted = f.value("adapted_contrast_threshold", nlohmann::json::object());
    if (!adapted.empty()) {
      double lowest = 1.0;
      for (const auto& [name, c] : adapted.items()) lowest = std::min(lowest, c.get<double>());
      Row(h, "images with a lowered SIFT contrast threshold (too few features)",
          std::to_string(adapted.size()) + ", down to " + FormatNumber("%.4g", lowest));
    }
  }
  // The view graph and the tracks the result was made from (the second matching's when the run
  // matched again, the pairs verified again when focals were estimated).
  if (r.contains("stages") && r["stages"].is_object()) {
    const nlohmann::json& st = r["stages"];
    const auto last_of = [&](const char* second, const char* first) -> const nlohmann::json* {
      if (st.contains(second)) return &st[second];
      return st.contains(first) ? &st[first] : nullptr;
    };
    const nlohmann::json* pairs = last_of("pairs_recalibrated", "pairs");
    if (pairs && pairs->contains("pairs_kept") && pairs->contains("pairs_kept_front_end"))
      Row(h, "image pairs verified (view graph)",
          std::to_string((*pairs)["pairs_kept"].get<long>()) + " (" +
              std::to_string((*pairs)["pairs_kept_front_end"].get<long>()) + " with the matching's geometry, " +
              std::to_string(pairs->value("pairs_kept_ransac", 0L)) + " by RANSAC on the tracks)");
    const nlohmann::json* match = last_of("match_recalibrated", "match");
    if (match && match->contains("tracks")) Row(h, "tracks (points seen in 2 or more images)", std::to_string((*match)["tracks"].get<long>()));
  }
  if (in.model) {
    Row(h, "points", std::to_string(in.model->points3D.size()));
    Row(h, "observations", std::to_string(in.model->NumObservations()));
  }
  if (r.contains("params")) Row(h, "unknowns of the pointless global BA", std::to_string(r["params"].get<long>()));
  if (in.convergence && !in.convergence->empty()) {
    const std::string note = ConvergenceSampleNote(in);
    Row(h, "sigma initial poses (px" + note + ")", FormatNumber("%.4f", in.convergence->front()));
  }
  // The result's sigma, the console's evaluation's: the curve's last point is a sample's, or
  // with the cameras the adjustment began with when it self-calibrated.
  if (in.metrics && in.metrics->sigma.Computable())
    Row(h, "sigma final (px)", FormatNumber("%.4f", in.metrics->sigma.rms));
  else if (in.convergence && !in.convergence->empty())
    Row(h, "sigma final (px" + ConvergenceSampleNote(in) + ")", FormatNumber("%.4f", in.convergence->back()));
  if (in.metrics) {
    if (in.metrics->sigma.Computable()) {
      Row(h, "sigma median (px)", FormatNumber("%.4f", in.metrics->sigma.median));
      Row(h, "inlier fraction (< 4 px)", FormatNumber("%.4f", in.metrics->sigma.inlier_fraction));
    }
    if (in.metrics->ground_truth && in.metrics->ground_truth->ok) {
      const GroundTruthErrors& g = *in.metrics->ground_truth;
      Row(h, "rotation error vs ground truth, median / max (deg)",
          FormatNumber("%.4f", g.rot_err_deg_median) + " / " + FormatNumber("%.4f", g.rot_err_deg_max));
      Row(h, "centre error vs ground truth, median / max (fraction of extent)",
          FormatNumber("%.2e", g.center_err_rel_median) + " / " + FormatNumber("%.2e", g.center_err_rel_max));
    }
  }
  h << "</table>\n";

  DroppedImagesTable(h, r);
  ModelView3d view;
  if (in.models || in.model) {
    view = MakeModelView3d(in.models ? *in.models : std::vector<const Reconstruction*>{in.model});
    h << ModelView3dSection(view);
  }
  if (r.contains("intrinsics") && r["intrinsics"].is_array() && !r["intrinsics"].empty())
    IntrinsicsTable(h, r["intrinsics"]);

  if (r.contains("stages")) StagesTable(h, r);
  GlobalBaPasses(h, r);
  if (in.convergence && !in.convergence->empty()) {
    PlotSeries s{"pointless global BA", {}, *in.convergence};
    for (size_t i = 0; i < s.y.size(); ++i) s.x.push_back(static_cast<double>(i));
    PlotOptions o;
    o.title = "sigma per iteration" + ConvergenceSampleNote(in);
    o.x_label = "iteration";
    o.y_label = "sigma (px)";
    o.log_y = true;
    o.integer_x = true;
    h << "<h2>Convergence</h2>\n" << LinePlotSvg({s}, o);
  }
  if (in.model) h << "<h2>Top view</h2><p>cameras (red, with viewing direction) and points</p>\n" << TopViewSvg(*in.model);
  if (in.view_graph && !in.view_graph->images.empty()) {
    const auto& im = in.view_graph->images;
    h << "<h2>View graph</h2><p>" << in.view_graph->edges.size() << " verified pairs; images 1 ("
      << XmlEscape(im.front().name) << ") to " << im.size() << " (" << XmlEscape(im.back().name)
      << ") in name order, hollow red: not registered (hover for names and inliers)</p>\n"
      << ViewGraphSvg(*in.view_graph) << ViewGraphTable(*in.view_graph);
  }
  h << "<h2>Files</h2><ul><li><code>sparse/</code>: COLMAP text model</li><li><code>points.ply</code></li>"
       "<li><code>report.json</code>: every stage's record</li><li><code>log.txt</code></li></ul>\n";
  h << ModelView3dScripts(view) << "</body></html>\n";
  return h.str();
}

}  // namespace pgba
