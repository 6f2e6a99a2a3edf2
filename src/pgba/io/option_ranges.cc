#include "pgba/io/option_ranges.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "matching/relative_pose_method.h"
#include "pgba/util/error.h"

namespace pgba {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

OptionRange Above(double v) { return {v, kInf, true, false, true, false}; }      // > v
OptionRange AtLeast(double v) { return {v, kInf, true, false, false, false}; }   // >= v
OptionRange Closed(double a, double b) { return {a, b, true, true, false, false}; }
OptionRange Open(double a, double b) { return {a, b, true, true, true, true}; }
OptionRange HalfOpen(double a, double b) { return {a, b, true, true, true, false}; }  // (a, b]
OptionRange Unbounded() { return {}; }  // documented meaning for every value (<= 0: off; seeds)

const OptionRange kPositive = Above(0);
const OptionRange kNonNegative = AtLeast(0);
const OptionRange kAtLeastOne = AtLeast(1);
const OptionRange kFraction = Closed(0, 1);
const OptionRange kProbability = Open(0, 1);     // RANSAC confidence: 1 never stops, 0 never samples
const OptionRange kAngleDeg = HalfOpen(0, 180);  // a positive angle threshold
const OptionRange kMinAngleDeg = Closed(0, 180);  // a lower bound on an angle, 0 = none

using Table = std::map<std::string, OptionRange>;

// BundleAdjusterOptions (optim/bundle_adjuster.h) under `prefix`.
void AddBundleAdjuster(const std::string& prefix, Table* t) {
  (*t)[prefix + ".loss_scale_px"] = kPositive;
  (*t)[prefix + ".dense_schur_max_poses"] = kNonNegative;
  (*t)[prefix + ".max_iterations"] = kAtLeastOne;
  (*t)[prefix + ".function_tolerance"] = kNonNegative;
  (*t)[prefix + ".gradient_tolerance"] = kNonNegative;
  (*t)[prefix + ".parameter_tolerance"] = kNonNegative;
  (*t)[prefix + ".num_threads"] = kNonNegative;  // 0 = all
}

// RelativePoseOptions (matching/relative_pose.h) under `prefix`.
void AddRelativePose(const std::string& prefix, Table* t) {
  (*t)[prefix + ".threshold_px"] = kPositive;
  (*t)[prefix + ".max_iterations"] = kAtLeastOne;
  (*t)[prefix + ".confidence"] = kProbability;
  (*t)[prefix + ".seed"] = Unbounded();
  (*t)[prefix + ".huber_px"] = kPositive;
  (*t)[prefix + ".refine_passes"] = kAtLeastOne;  // refine + re-classify passes after RANSAC
  (*t)[prefix + ".max_refine_correspondences"] = AtLeast(5);  // the 5-point minimum
  (*t)[prefix + ".min_inliers"] = AtLeast(5);
}

Table BuildTable() {
  Table t;
  // features (features/extract_features.h, sift_extractor.h)
  t["features.sift.max_features"] = kAtLeastOne;
  t["features.sift.max_image_size"] = Unbounded();  // <= 0 disables the downscaling
  t["features.sift.contrast_threshold"] = kPositive;
  t["features.sift.edge_threshold"] = kPositive;
  t["features.sift.target_features"] = Unbounded();  // <= 0: off
  t["features.sift.min_contrast_threshold"] = kPositive;
  t["features.sift.first_octave"] = Closed(-1, 0);  // -1: 2x upsampled (OpenCV, COLMAP default), 0: as is
  t["features.max_parallel_images"] = kNonNegative;  // 0 = one per core
  // matching (matching/*.h)
  t["matching.pairs.window"] = kAtLeastOne;
  t["matching.pairs.vlad.neighbors"] = kAtLeastOne;
  t["matching.pairs.vlad.num_words"] = kAtLeastOne;
  t["matching.pairs.vlad.max_training_descriptors"] = kAtLeastOne;
  t["matching.pairs.vlad.kmeans_iterations"] = kAtLeastOne;
  t["matching.pairs.vlad.seed"] = Unbounded();
  t["matching.descriptors.max_ratio"] = HalfOpen(0, 1);
  t["matching.descriptors.max_distance"] = kPositive;
  t["matching.descriptors.kdtree_trees"] = kAtLeastOne;
  t["matching.descriptors.checks"] = kAtLeastOne;
  t["matching.descriptors.cascade_hashing.num_tables"] = Closed(1, 32);
  t["matching.descriptors.cascade_hashing.bits_per_bucket"] = Closed(1, 16);
  t["matching.descriptors.cascade_hashing.target_bucket_size"] = kAtLeastOne;
  t["matching.descriptors.cascade_hashing.num_reranked"] = kAtLeastOne;
  AddRelativePose("matching.verification.relative_pose", &t);
  t["matching.verification.min_inlier_ratio"] = kFraction;
  t["matching.verification.max_rotation_sd_deg"] = kAngleDeg;
  t["matching.verification.guided.max_inliers"] = kAtLeastOne;
  t["matching.verification.guided.min_inliers"] = AtLeast(8);  // 5-point solver + 3 to choose
  t["matching.verification.guided.threshold_px"] = kPositive;
  t["matching.verification.guided.max_ratio"] = HalfOpen(0, 1);
  t["matching.verification.guided.max_distance"] = kPositive;
  t["matching.verification.weak_pairs.min_inliers"] = AtLeast(8);  // 5-point solver + 3 to choose
  t["matching.verification.weak_pairs.max_rotation_sd_deg"] = kPositive;
  t["matching.verification.weak_pairs.max_verified_pairs"] = kNonNegative;
  t["matching.verification.weak_pairs.max_rotation_cycle_deg"] = kAngleDeg;
  t["matching.verification.weak_pairs.max_coplanarity_deg"] = HalfOpen(0, 90);
  t["matching.verification.weak_pairs.min_closed_matches"] = kNonNegative;
  t["matching.tracks.min_track_length"] = AtLeast(2);
  t["matching.max_indexed_images"] = AtLeast(2);  // both images of a pair
  // pairs (triplets/pair_estimation.h)
  t["pairs.min_shared_tracks"] = AtLeast(5);
  t["pairs.max_pairs_per_image"] = kNonNegative;  // 0 = no limit
  AddRelativePose("pairs.relative_pose", &t);
  t["pairs.min_inliers"] = AtLeast(5);
  t["pairs.min_inlier_ratio"] = kFraction;
  t["pairs.min_triangulation_angle_deg"] = kMinAngleDeg;
  t["pairs.seed"] = Unbounded();
  // convergence (mapper/convergence_curve.h)
  t["convergence.max_tracks"] = kNonNegative;  // 0 = every track
  // verification (mapper/image_verification.h)
  t["verification.inlier_px"] = kPositive;
  t["verification.min_triangulation_angle_deg"] = Closed(0, 90);
  t["verification.min_checked_observations"] = AtLeast(3);
  t["verification.min_inlier_ratio"] = kFraction;
  t["verification.max_pair_rotation_deg"] = kPositive;
  // components (mapper/components.h)
  t["components.min_correspondences"] = AtLeast(4);  // P3P + one to choose
  t["components.min_pose_inliers"] = AtLeast(4);
  t["components.pose_threshold_px"] = kPositive;
  t["components.min_inlier_ratio"] = kFraction;
  t["components.max_pair_rotation_deg"] = kPositive;
  t["components.min_shared_points"] = AtLeast(3);  // a 3-point similarity
  t["components.min_merge_pairs"] = AtLeast(2);    // one pair leaves the scale free
  t["components.min_agreeing_pairs_ratio"] = kFraction;
  t["components.max_merge_rotation_deg"] = kAngleDeg;
  t["components.max_merge_direction_deg"] = kAngleDeg;
  t["components.max_rounds"] = kAtLeastOne;
  // calibration (calibration/view_graph_calibration.h, fundamental_matrix.h)
  t["calibration.fundamental.threshold_px"] = kPositive;
  t["calibration.fundamental.confidence"] = kProbability;
  t["calibration.fundamental.max_iterations"] = kAtLeastOne;
  t["calibration.fundamental.min_inliers"] = AtLeast(8);  // the 8-point refinement's minimum
  t["calibration.fundamental.refine_iterations"] = kNonNegative;  // 0 = the RANSAC model as is
  t["calibration.fundamental.huber_px"] = kPositive;
  t["calibration.loss_scale"] = kPositive;
  t["calibration.min_focal_ratio"] = Open(0, 1);
  t["calibration.max_focal_ratio"] = Above(1);
  t["calibration.min_pairs"] = AtLeast(2);  // a standard deviation needs two residuals
  t["calibration.max_relative_sd"] = kPositive;
  t["calibration.max_sweeps"] = kAtLeastOne;
  t["calibration.max_pairs_per_camera"] = kNonNegative;  // 0 = all
  t["calibration.max_abs_k1"] = HalfOpen(0, 1);
  t["calibration.max_homography_inlier_ratio"] = kPositive;  // >= 1: no test
  t["calibration.rematch_shift_px"] = kNonNegative;  // 0 = never
  // triplets (triplets/triplet_options.h, absolute_pose.h)
  t["triplets.max_triplets_per_image"] = kAtLeastOne;
  t["triplets.max_selection_rounds"] = kAtLeastOne;
  t["triplets.max_rotation_cycle_deg"] = kAngleDeg;
  t["triplets.open_min_tracks_all_views"] = kAtLeastOne;
  t["triplets.absolute_pose.threshold_px"] = kPositive;
  t["triplets.absolute_pose.max_iterations"] = kAtLeastOne;
  t["triplets.absolute_pose.confidence"] = kProbability;
  t["triplets.absolute_pose.seed"] = Unbounded();
  t["triplets.absolute_pose.min_inliers"] = AtLeast(3);  // the P3P minimum
  t["triplets.outlier_threshold_px"] = kPositive;
  t["triplets.min_track_angle_deg"] = kMinAngleDeg;
  AddBundleAdjuster("triplets.bundle_adjuster", &t);
  t["triplets.min_tracks"] = kAtLeastOne;
  t["triplets.max_rms_px"] = kPositive;
  t["triplets.intrinsics_max_sd_px"] = kPositive;
  t["triplets.min_triangulation_angle_deg"] = kMinAngleDeg;
  t["triplets.score_angle_deg"] = kAngleDeg;
  t["triplets.seed"] = Unbounded();
  // global_init (averaging/*.h)
  t["global_init.pair_validation.max_rotation_deg"] = kAngleDeg;
  t["global_init.pair_validation.max_direction_deg"] = kAngleDeg;
  t["global_init.rotation.observations.pair_weight"] = kNonNegative;
  t["global_init.rotation.observations.triplet_weight"] = kNonNegative;
  t["global_init.rotation.init_consistency_deg"] = kAngleDeg;
  t["global_init.rotation.max_l1_iterations"] = kNonNegative;  // 0 disables the L1 stage
  t["global_init.rotation.l1_inner_iterations"] = kAtLeastOne;
  t["global_init.rotation.l1_step_tolerance_deg"] = kPositive;
  t["global_init.rotation.loss_scale_deg"] = kAngleDeg;
  t["global_init.rotation.max_irls_iterations"] = kNonNegative;
  t["global_init.rotation.step_tolerance_deg"] = kPositive;
  t["global_init.rotation.inlier_threshold_deg"] = kAngleDeg;
  t["global_init.translation.scale_loss_scale"] = kPositive;
  t["global_init.translation.centre_loss_scale"] = kPositive;
  t["global_init.translation.max_irls_iterations"] = kAtLeastOne;
  t["global_init.translation.irls_tolerance"] = kPositive;
  t["global_init.translation.pair_weight"] = kNonNegative;
  t["global_init.translation.triplet_weight"] = kPositive;
  t["global_init.translation.refine_huber"] = kPositive;
  t["global_init.translation.max_refine_iterations"] = kNonNegative;
  t["global_init.translation.num_threads"] = kNonNegative;
  t["global_init.track_positioning.loss_scale_px"] = kPositive;
  t["global_init.track_positioning.min_track_angle_deg"] = kMinAngleDeg;
  t["global_init.track_positioning.max_iterations"] = kNonNegative;
  t["global_init.track_positioning.num_threads"] = kNonNegative;
  t["global_init.max_triplet_rotation_error_deg"] = Unbounded();  // <= 0 keeps every triplet
  t["global_init.max_triplet_centre_error"] = Unbounded();        // <= 0 keeps every triplet
  // local_motions, local_hessian (local_hessian/*.h)
  t["local_motions.views"] = AtLeast(3);
  t["local_motions.max_views"] = AtLeast(2);
  t["local_motions.min_tracks"] = kAtLeastOne;
  t["local_motions.min_shared_tracks"] = kAtLeastOne;
  t["local_motions.max_iterations"] = kNonNegative;
  t["local_motions.neighbour_strides[]"] = kAtLeastOne;
  t["local_motions.triplet_start_misfit"] = Unbounded();  // <= 0: never
  t["local_motions.triplet_start_max_iterations"] = kAtLeastOne;
  t["local_motions.triplet_start_max_per_image"] = Unbounded();  // <= 0: every triplet
  t["local_hessian.max_iterations"] = kNonNegative;
  t["local_hessian.attenuation_q"] = Unbounded();  // <= 0 disables the attenuation
  t["local_hessian.huber_px"] = kPositive;
  t["local_hessian.max_reprojection_px"] = kPositive;
  t["local_hessian.cauchy_max_reprojection_px"] = kPositive;
  t["local_hessian.min_points"] = kAtLeastOne;
  t["local_hessian.prior_relative"] = kPositive;
  t["local_hessian.min_eigenvalue_ratio"] = kNonNegative;
  t["local_hessian.min_triangulation_angle_deg"] = kMinAngleDeg;
  t["local_hessian.num_threads"] = kNonNegative;
  // global_ba (global_ba/global_ba.h)
  t["global_ba.max_rounds"] = kAtLeastOne;
  t["global_ba.max_iterations_per_round"] = kAtLeastOne;
  t["global_ba.round_tolerance"] = kNonNegative;
  t["global_ba.function_tolerance"] = kNonNegative;
  t["global_ba.parameter_tolerance"] = kNonNegative;
  t["global_ba.initial_trust_region_radius"] = kPositive;
  t["global_ba.embedded_similarity_iterations"] = kNonNegative;
  t["global_ba.irls_factor"] = Unbounded();   // <= 0 disables the reweighting
  t["global_ba.huber_factor"] = Unbounded();  // <= 0 disables the Huber loss
  t["global_ba.scalar_rotation_sigma"] = kPositive;
  t["global_ba.scalar_position_sigma"] = kPositive;
  t["global_ba.num_threads"] = kNonNegative;
  t["global_ba.max_relinearizations"] = kNonNegative;
  t["global_ba.relinearize_misfit"] = Unbounded();  // <= 0: always
  t["global_ba.relinearize_tolerance"] = kPositive;
  t["global_ba.relinearize_cost_tolerance"] = kNonNegative;
  t["global_ba.relinearized_function_tolerance"] = kNonNegative;
  t["global_ba.start_outlier_factor"] = Unbounded();  // <= 0: off
  // point_based (mapper/pose_refinement.h)
  AddBundleAdjuster("point_based.bundle", &t);
  t["point_based.filter_max_error_px"] = Unbounded();  // <= 0: a single pass
  // gcp (global_ba/gcp_constraint.h)
  t["gcp.default_sigma"] = kPositive;
  t["gcp.huber_sigmas"] = Unbounded();  // <= 0: plain least squares
  t["gcp.min_angle_deg"] = kMinAngleDeg;
  // Options structs that are no config section, under their struct's name (their Check()).
  t["SiftDetectionOptions.contrast_threshold"] = kPositive;  // features/sift_keypoints.h
  t["SiftDetectionOptions.edge_threshold"] = kPositive;
  t["SiftDetectionOptions.max_features"] = Unbounded();  // <= 0: every extremum oriented
  t["OutlierInjectionOptions.fraction"] = kFraction;  // averaging/outlier_injection.h
  t["OutlierInjectionOptions.seed"] = Unbounded();
  t["SigmaOptions.inlier_px"] = kPositive;  // evaluation/sigma.h
  t["SigmaOptions.huber_px"] = kPositive;
  t["SigmaOptions.max_iterations"] = kNonNegative;
  t["GroundTruthOptions.outlier_factor"] = kPositive;  // evaluation/ground_truth.h: x the median error
  t["GroundTruthOptions.max_rounds"] = kNonNegative;
  t["TriangulationOptions.huber_px"] = kPositive;  // geometry/triangulation.h
  t["TriangulationOptions.outlier_px"] = kPositive;
  t["TriangulationOptions.max_iterations"] = kNonNegative;
  t["TriangulationOptions.min_angle_deg"] = kMinAngleDeg;
  t["ProceduralTextureOptions.largest_cell"] = kAtLeastOne;  // synthetic/procedural_texture.h
  for (const char* density : {"blobs_per_10k", "texts_per_10k", "lines_per_10k", "blur_sigma"})
    t[std::string("ProceduralTextureOptions.") + density] = kNonNegative;
  t["ProceduralTextureOptions.min_blob"] = kPositive;
  t["ProceduralTextureOptions.max_blob"] = kPositive;
  t["EssentialRansacOptions.threshold_angle"] = kPositive;  // matching/essential_ransac.h, radians
  t["EssentialRansacOptions.max_iterations"] = kAtLeastOne;
  t["EssentialRansacOptions.confidence"] = kProbability;
  t["EssentialRansacOptions.min_iterations"] = kNonNegative;
  t["PlotOptions.width"] = kAtLeastOne;  // report/svg_plot.h, pixels
  t["PlotOptions.height"] = kAtLeastOne;
  t["WholeTrackMotionOptions.max_views"] = AtLeast(2);  // local_hessian/whole_track_motions.h
  t["WholeTrackMotionOptions.min_tracks"] = kAtLeastOne;
  t["BenchmarkOptions.outlier_sweep[]"] = kFraction;  // benchmark/benchmark.h
  return t;
}

const Table& RangeTable() {
  static const Table table = BuildTable();
  return table;
}

std::string Number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

// String options that name a method, by dotted path: their valid values, the matcher's own
// names (matching/relative_pose_method.h). Without this a typo ("samspon") passed the config
// check and ended the run in the matcher with a bare std::invalid_argument that named
// neither the file nor the key.
const std::map<std::string, std::vector<std::string>>& ChoiceTable() {
  static const std::map<std::string, std::vector<std::string>> table = [] {
    std::map<std::string, std::vector<std::string>> t;
    for (const std::string prefix : {"matching.verification.relative_pose", "pairs.relative_pose"}) {
      t[prefix + ".scoring"] = MethodNames(kPoseScoringNames);   // RelativePoseOptions::scoring
      t[prefix + ".algorithm"] = MethodNames(kPoseSolverNames);  // RelativePoseOptions::algorithm
    }
    // LossType names (optim/loss_function_options.h) these estimators are written for.
    t["local_hessian.loss"] = {"huber", "cauchy", "trivial"};
    for (const std::string prefix : {"triplets.bundle_adjuster", "point_based.bundle"}) {  // BundleAdjusterOptions
      t[prefix + ".loss"] = {"huber", "cauchy", "trivial"};
      t[prefix + ".linear_solver"] = {"auto", "dense_schur", "sparse_schur", "iterative_schur"};
    }
    t["matching.descriptors.method"] = {"cascade_hashing", "kdtree"};  // matching/descriptor_matcher.h
    t["matching.pairs.method"] = {"exhaustive", "sequential", "retrieval"};  // matching/pair_selection.h
    t["triplets.absolute_pose.algorithm"] = {"p3p_kneip", "p3p_gao", "epnp"};  // triplets/absolute_pose.cc
    t["EssentialRansacOptions.algorithm"] = MethodNames(kPoseSolverNames);
    t["point_based.first_pass_loss"] = {"", "huber", "cauchy", "trivial"};  // "": the bundle's loss
    return t;
  }();
  return table;
}

// The first value of `value` (at dotted `path`) outside its range or choices: "KEY = VALUE is
// out of range (RANGE)" / "KEY = VALUE is not one of: A, B", KEY without the first `strip`
// characters of the path; empty if every value is valid.
std::string FirstInvalid(const nlohmann::json& value, const std::string& path, size_t strip) {
  if (value.is_object()) {
    for (const auto& [key, child] : value.items()) {
      const std::string m = FirstInvalid(child, path.empty() ? key : path + "." + key, strip);
      if (!m.empty()) return m;
    }
    return "";
  }
  if (value.is_array()) {
    for (const nlohmann::json& element : value) {
      const std::string m = FirstInvalid(element, path + "[]", strip);
      if (!m.empty()) return m;
    }
    return "";
  }
  const std::string key = path.substr(std::min(strip, path.size()));
  if (value.is_string()) {
    const auto it = ChoiceTable().find(path);
    if (it == ChoiceTable().end()) return "";
    const std::string v = value.get<std::string>();
    std::string list;
    for (const std::string& c : it->second) {
      if (v == c) return "";
      list += (list.empty() ? "" : ", ") + c;
    }
    return key + " = " + value.dump() + " is not one of: " + list;
  }
  if (!value.is_number()) return "";
  const std::optional<OptionRange> range = RangeOfOption(path);
  if (!range || range->Contains(value.get<double>())) return "";
  const std::string bounds = range->Describe();  // "[0, 1]", "(0, 1)" or "> 0"
  const bool bracketed = bounds[0] == '[' || bounds[0] == '(';
  return key + " = " + value.dump() + " is out of range " + (bracketed ? bounds : "(" + bounds + ")");
}

}  // namespace

std::string OptionRange::Describe() const {
  if (!has_min && !has_max) return "any";
  if (has_min && std::isinf(max)) return std::string(min_open ? "> " : ">= ") + Number(min);
  return std::string(min_open ? "(" : "[") + Number(min) + ", " + Number(max) + (max_open ? ")" : "]");
}

bool OptionRange::Contains(double v) const {
  if (!std::isfinite(v)) return false;
  if (has_min && (min_open ? !(v > min) : !(v >= min))) return false;
  if (has_max && (max_open ? !(v < max) : !(v <= max))) return false;
  return true;
}

std::optional<OptionRange> RangeOfOption(const std::string& dotted_path) {
  const auto it = RangeTable().find(dotted_path);
  if (it == RangeTable().end()) return std::nullopt;
  return it->second;
}

void CheckOptionRanges(const nlohmann::json& root, const std::string& origin) {
  const std::string invalid = FirstInvalid(root, "", 0);
  if (!invalid.empty()) ThrowInputError(origin, 0, invalid);
}

std::string CheckRangesAt(const nlohmann::json& options, const std::string& section) {
  return FirstInvalid(options, section, section.size() + 1);
}

}  // namespace pgba
