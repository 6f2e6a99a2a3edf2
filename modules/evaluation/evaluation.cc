#include "evaluation/evaluation.h"

#include <cstdio>
#include <string>

#include "pgba/util/text_format.h"

namespace pgba {

EvaluationMetrics Evaluate(const Reconstruction& model, const Reconstruction& obs, const Reconstruction* gt,
                           const std::vector<LoopCorrespondence>* loops, const EvaluationOptions& options) {
  EvaluationMetrics m;
  const RegisteredViews views = MatchImagesByName(model, obs);
  m.images_input = obs.images.size();
  m.images_registered = views.poses.size();
  m.sigma = EvaluateSigma(obs, views.poses, options.sigma, &views.cameras);
  if (gt) m.ground_truth = CompareToGroundTruth(model, *gt, options.ground_truth);
  if (loops) m.loop = EvaluateLoopClosure(model, *loops);
  return m;
}

nlohmann::json EvaluationMetrics::ToJson() const {
  nlohmann::json j, details;
  j["images_input"] = images_input;
  j["images_registered"] = images_registered;
  details["tracks"] = sigma.num_tracks;
  details["tracks_triangulated"] = sigma.num_triangulated;
  details["observations"] = sigma.num_observations;
  if (sigma.Computable()) j["sigma_rms"] = sigma.rms;
  if (sigma.num_triangulated > 0) j["sigma_median"] = sigma.median;
  if (sigma.num_observations > 0) j["inlier_fraction"] = sigma.inlier_fraction;
  if (sigma.num_observations > 0) j["robust_cost"] = sigma.robust_cost;
  if (ground_truth) {
    details["gt_images_common"] = ground_truth->num_common;
    if (ground_truth->ok) {
      j["rot_err_deg_median"] = ground_truth->rot_err_deg_median;
      j["rot_err_deg_max"] = ground_truth->rot_err_deg_max;
      j["center_err_rel_median"] = ground_truth->center_err_rel_median;
      j["center_err_rel_max"] = ground_truth->center_err_rel_max;
    }
    if (ground_truth->num_pairs > 0) {
      j["rel_rot_err_deg_median"] = ground_truth->rel_rot_err_deg_median;
      j["rel_rot_err_deg_max"] = ground_truth->rel_rot_err_deg_max;
      j["rel_dir_err_deg_median"] = ground_truth->rel_dir_err_deg_median;
      j["rel_dir_err_deg_max"] = ground_truth->rel_dir_err_deg_max;
      details["gt_pairs"] = ground_truth->num_pairs;
    }
    if (ground_truth->ok) {
      details["gt_alignment_inliers"] = ground_truth->num_alignment_inliers;
      details["gt_centres_collinearity"] = ground_truth->collinearity;
      details["gt_scene_extent"] = ground_truth->scene_extent;
    }
  }
  if (loop) {
    details["loop_correspondences"] = loop->num_correspondences;
    details["loop_evaluated"] = loop->num_evaluated;
    details["loop_failed"] = loop->num_failed;
    details["loop_unregistered"] = loop->num_unregistered;
    if (loop->Computable()) {
      j["loop_err_rms"] = loop->rms;
      j["loop_err_median"] = loop->median;
    }
  }
  j["details"] = details;
  return j;
}

namespace {

void Row(std::ostream& out, const std::string& name, const std::string& value) {
  char buf[160];
  std::snprintf(buf, sizeof(buf), "  %-24s %s\n", name.c_str(), value.c_str());
  out << buf;
}

}  // namespace

void EvaluationMetrics::PrintTable(std::ostream& out, const std::string& title) const {
  const std::string na = "n/a";
  out << title << "\n";
  Row(out, "images registered", std::to_string(images_registered) + " / " + std::to_string(images_input));
  Row(out, "tracks triangulated", std::to_string(sigma.num_triangulated) + " of " + std::to_string(sigma.num_tracks) +
                                        " seen in 2 or more registered images");
  Row(out, "sigma rms (px)", sigma.Computable() ? FormatNumber("%.4f", sigma.rms) : na);
  Row(out, "sigma median (px)", sigma.num_triangulated > 0 ? FormatNumber("%.4f", sigma.median) : na);
  Row(out, "inlier fraction", sigma.num_observations > 0 ? FormatNumber("%.4f", sigma.inlier_fraction) : na);
  if (ground_truth) {
    const GroundTruthErrors& g = *ground_truth;
    Row(out, "gt images compared", std::to_string(g.num_common) + " (alignment on " +
                                       std::to_string(g.num_alignment_inliers) + ")");
    Row(out, "rot err median (deg)", g.ok ? FormatNumber("%.4g", g.rot_err_deg_median) : na);
    Row(out, "rot err max (deg)", g.ok ? FormatNumber("%.4g", g.rot_err_deg_max) : na);
    Row(out, "centre err median (rel)", g.ok ? FormatNumber("%.3e", g.center_err_rel_median) : na);
    Row(out, "centre err max (rel)", g.ok ? FormatNumber("%.3e", g.center_err_rel_max) : na);
    const bool pairs = g.num_pairs > 0;
    Row(out, "rel. rot err med (deg)", pairs ? FormatNumber("%.4g", g.rel_rot_err_deg_median) : na);
    Row(out, "rel. rot err max (deg)", pairs ? FormatNumber("%.4g", g.rel_rot_err_deg_max) : na);
    Row(out, "rel. dir err med (deg)", pairs ? FormatNumber("%.4g", g.rel_dir_err_deg_median) : na);
    Row(out, "rel. dir err max (deg)", pairs ? FormatNumber("%.4g", g.rel_dir_err_deg_max) : na);
  }
  if (loop) {
    Row(out, "loop pairs evaluated", std::to_string(loop->num_evaluated) + " / " +
                                         std::to_string(loop->num_correspondences) +
                                         (loop->num_failed ? " (" + std::to_string(loop->num_failed) + " failed)" : ""));
    Row(out, "loop err rms (px)", loop->Computable() ? FormatNumber("%.4f", loop->rms) : na);
    Row(out, "loop err median (px)", loop->Computable() ? FormatNumber("%.4f", loop->median) : na);
  }
}

std::string EvaluationOptions::Check() const {
  if (const std::string p = sigma.Check(); !p.empty()) return "sigma." + p;
  if (const std::string p = ground_truth.Check(); !p.empty()) return "ground_truth." + p;
  return "";
}

}  // namespace pgba
