#include "mapper/image_verification.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "pgba/geometry/rotation.h"
#include "pgba/geometry/triangulation.h"
#include "pgba/io/option_ranges.h"
#include "pgba/util/text_format.h"
#include "pgba/util/upper_median.h"

namespace pgba {

std::string ImageVerificationOptions::Check() const { return CheckRanges(*this, "verification"); }

namespace {

// The image's observations paired with their leave-one-out points.
struct Correspondences {
  std::vector<Eigen::Vector2d> pixels;
  std::vector<Eigen::Vector3d> points;
};

Correspondences LeaveOneOutPoints(const Reconstruction& tracks, const std::map<uint32_t, Pose>& poses,
                                  uint32_t image_id, const ImageVerificationOptions& options) {
  Correspondences c;
  TriangulationOptions triangulation;
  triangulation.outlier_px = options.inlier_px;
  triangulation.min_angle_deg = options.min_triangulation_angle_deg;
  const Image& image = tracks.images.at(image_id);
  for (const Point2D& p : image.points2D) {
    if (p.point3D_id == kNoPoint3D) continue;
    const auto track = tracks.points3D.find(static_cast<uint64_t>(p.point3D_id));
    if (track == tracks.points3D.end()) continue;
    std::vector<TrackView> views;
    for (const TrackElement& el : track->second.track) {
      if (el.image_id == image_id) continue;
      const auto pose = poses.find(el.image_id);
      if (pose == poses.end()) continue;
      const Image& other = tracks.images.at(el.image_id);
      views.push_back({pose->second, &tracks.cameras.at(other.camera_id), other.points2D[el.point2D_idx].xy});
    }
    if (views.size() < 2) continue;
    const TriangulatedPoint X = TriangulateTrack(views, triangulation);
    if (!X.ok) continue;
    c.pixels.push_back(p.xy);
    c.points.push_back(X.X);
  }
  return c;
}

// The verified pairs of each image (indices into `pairs`).
std::map<uint32_t, std::vector<size_t>> PairsByImage(const std::vector<TwoViewGeometry>& pairs) {
  std::map<uint32_t, std::vector<size_t>> out;
  for (size_t k = 0; k < pairs.size(); ++k) {
    out[pairs[k].image_id1].push_back(k);
    out[pairs[k].image_id2].push_back(k);
  }
  return out;
}

ImageEvidence Evidence(const Reconstruction& tracks, const Correspondences& c,
                       const std::vector<TwoViewGeometry>& pairs,
                       const std::vector<size_t>* own_pairs, const std::map<uint32_t, Pose>& poses, uint32_t image_id,
                       const Pose& pose, const ImageVerificationOptions& options) {
  ImageEvidence e;
  const Camera& camera = tracks.cameras.at(tracks.images.at(image_id).camera_id);
  const Eigen::Matrix3d R = pose.R();
  const Eigen::Vector3d C = pose.C();
  for (size_t k = 0; k < c.points.size(); ++k) {
    ++e.observations_checked;
    const Eigen::Vector3d x = R * (c.points[k] - C);
    if (!(x.z() > 0)) continue;
    if ((camera.Project(x) - c.pixels[k]).norm() < options.inlier_px) ++e.inliers;
  }
  std::vector<double> angles;
  if (own_pairs) {
    for (const size_t k : *own_pairs) {
      const TwoViewGeometry& g = pairs[k];
      const uint32_t other = g.image_id1 == image_id ? g.image_id2 : g.image_id1;
      const auto p = poses.find(other);
      if (p == poses.end() || other == image_id) continue;
      const Eigen::Matrix3d R1 = g.image_id1 == image_id ? R : p->second.R();
      const Eigen::Matrix3d R2 = g.image_id2 == image_id ? R : p->second.R();
      angles.push_back(RotationAngleDeg(R2 * R1.transpose(), g.R_21));
    }
  }
  e.pairs_checked = static_cast<int>(angles.size());
  if (!angles.empty()) e.pair_rotation_deg = UpperMedian(angles);
  return e;
}

}  // namespace

std::string VerificationFailure(const ImageEvidence& e, const ImageVerificationOptions& options) {
  const bool by_points = e.observations_checked >= options.min_checked_observations;
  if (!by_points && e.pairs_checked == 0)
    return "unverifiable: " + std::to_string(e.observations_checked) +
           " observations of points seen by two other images and no verified pair with a registered image";
  if (by_points && e.inlier_ratio() < options.min_inlier_ratio)
    return std::to_string(e.inliers) + " of " + std::to_string(e.observations_checked) +
           " observations reproject within " + FormatNumber("%.1f", options.inlier_px) + " px (at least " +
           FormatNumber("%.0f", 100.0 * options.min_inlier_ratio) + "% needed)";
  if (e.pairs_checked > 0 && e.pair_rotation_deg > options.max_pair_rotation_deg)
    return "its rotation disagrees with its " + std::to_string(e.pairs_checked) + " verified image pairs by " +
           FormatNumber("%.1f", e.pair_rotation_deg) + " deg (median; at most " +
           FormatNumber("%.1f", options.max_pair_rotation_deg) +
           " allowed)";
  return "";
}

ImageEvidence MeasureImageEvidence(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                                   const std::map<uint32_t, Pose>& poses, uint32_t image_id, const Pose& pose,
                                   const ImageVerificationOptions& options) {
  const Correspondences c = LeaveOneOutPoints(tracks, poses, image_id, options);
  std::vector<size_t> own;
  for (size_t k = 0; k < pairs.size(); ++k)
    if (pairs[k].image_id1 == image_id || pairs[k].image_id2 == image_id) own.push_back(k);
  return Evidence(tracks, c, pairs, &own, poses, image_id, pose, options);
}

ImageVerificationResult VerifyRegisteredImages(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                                               const std::map<uint32_t, Pose>& poses,
                                               const ImageVerificationOptions& options) {
  ImageVerificationResult out;
  out.poses = poses;
  if (!options.enabled) return out;
  const std::map<uint32_t, std::vector<size_t>> by_image = PairsByImage(pairs);
  const auto own_pairs = [&](uint32_t id) -> const std::vector<size_t>* {
    const auto it = by_image.find(id);
    return it == by_image.end() ? nullptr : &it->second;
  };
  std::vector<uint32_t> ids;
  for (const auto& [id, pose] : poses) ids.push_back(id);
  out.verdicts.resize(ids.size());
  // 1. Every image at its adjusted pose, the others at theirs (per-index slots: deterministic).
  tbb::parallel_for(size_t(0), ids.size(), [&](size_t k) {
    const uint32_t id = ids[k];
    const Correspondences c = LeaveOneOutPoints(tracks, poses, id, options);
    ImageVerdict& v = out.verdicts[k];
    v.image_id = id;
    v.evidence = Evidence(tracks, c, pairs, own_pairs(id), poses, id, poses.at(id), options);
    v.reason = VerificationFailure(v.evidence, options);
  });
  // 2. The failing images leave the structure, then each is registered again against the
  //    images that stay (in id order; a re-registered image joins them for the next).
  std::vector<size_t> failing;
  for (size_t k = 0; k < ids.size(); ++k)
    if (!out.verdicts[k].reason.empty()) {
      failing.push_back(k);
      out.poses.erase(ids[k]);
    }
  for (const size_t k : failing) {
    ImageVerdict& v = out.verdicts[k];
    v.status = ImageVerdictStatus::kDropped;
    if (!options.reregister) continue;
    const uint32_t id = v.image_id;
    const Correspondences c = LeaveOneOutPoints(tracks, out.poses, id, options);
    if (static_cast<int>(c.points.size()) < options.min_checked_observations) {
      v.reason += "; not registered again: " + std::to_string(c.points.size()) + " points left to register it on";
      continue;
    }
    const Camera& camera = tracks.cameras.at(tracks.images.at(id).camera_id);
    std::vector<Eigen::Vector3d> bearings;
    for (const Eigen::Vector2d& px : c.pixels) bearings.push_back(camera.PixelToBearing(px));
    AbsolutePoseOptions pnp;
    pnp.threshold_px = options.inlier_px;
    pnp.min_inliers = options.min_checked_observations;
    pnp.seed = id;
    const AbsolutePoseResult a = EstimateAbsolutePose(bearings, c.points, camera.MeanFocal(), pnp);
    if (!a.success) {
      v.reason += "; not registered again: no absolute pose with " + std::to_string(pnp.min_inliers) +
                  " inliers among " + std::to_string(c.points.size()) + " points";
      continue;
    }
    v.reregistered = Evidence(tracks, c, pairs, own_pairs(id), out.poses, id, a.pose, options);
    const std::string again = VerificationFailure(v.reregistered, options);
    if (!again.empty()) {
      v.reason += "; registered again from the structure, that pose fails too: " + again;
      continue;
    }
    v.status = ImageVerdictStatus::kReregistered;
    v.moved_deg = RotationAngleDeg(a.pose.R(), poses.at(id).R());
    out.poses[id] = a.pose;
  }
  for (const ImageVerdict& v : out.verdicts) {
    out.num_reregistered += v.status == ImageVerdictStatus::kReregistered;
    out.num_dropped += v.status == ImageVerdictStatus::kDropped;
  }
  return out;
}

void KeepFirstVerdicts(const ImageVerificationResult& first, ImageVerificationResult* second) {
  std::map<uint32_t, size_t> index;
  for (size_t i = 0; i < second->verdicts.size(); ++i) index[second->verdicts[i].image_id] = i;
  for (const ImageVerdict& d : first.verdicts) {
    if (d.status == ImageVerdictStatus::kVerified) continue;
    const auto it = index.find(d.image_id);
    if (it == index.end()) {
      second->verdicts.push_back(d);
    } else if (second->verdicts[it->second].status == ImageVerdictStatus::kVerified) {
      second->verdicts[it->second] = d;
    } else {
      continue;
    }
    (d.status == ImageVerdictStatus::kDropped ? second->num_dropped : second->num_reregistered) += 1;
  }
  std::sort(second->verdicts.begin(), second->verdicts.end(),
            [](const ImageVerdict& a, const ImageVerdict& b) { return a.image_id < b.image_id; });
}

nlohmann::json ImageVerificationResult::ToJson(const Reconstruction& tracks) const {
  nlohmann::json images = nlohmann::json::array();
  for (const ImageVerdict& v : verdicts) {
    if (v.status == ImageVerdictStatus::kVerified) continue;
    const auto evidence = [](const ImageEvidence& e) {
      return nlohmann::json{{"observations_checked", e.observations_checked},
                            {"inliers", e.inliers},
                            {"pairs_checked", e.pairs_checked},
                            {"pair_rotation_deg", e.pair_rotation_deg}};
    };
    nlohmann::json j = {{"image", tracks.images.at(v.image_id).name},
                        {"status", v.status == ImageVerdictStatus::kReregistered ? "reregistered" : "dropped"},
                        {"reason", v.reason},
                        {"adjusted_pose", evidence(v.evidence)}};
    if (v.reregistered.observations_checked > 0) j["registered_again"] = evidence(v.reregistered);
    if (v.status == ImageVerdictStatus::kReregistered) j["moved_deg"] = v.moved_deg;
    images.push_back(std::move(j));
  }
  return {{"images_checked", verdicts.size()},
          {"images_verified", static_cast<int>(verdicts.size()) - num_reregistered - num_dropped},
          {"images_reregistered", num_reregistered},
          {"images_dropped", num_dropped},
          {"images", images}};
}

}  // namespace pgba
