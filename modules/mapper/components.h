// The models of one reconstruction, one per component of the triplet graph (InitialiseComponents,
// global_init.h), completed after their global BA by what connects the images:
//   - every image in no model is tried by absolute pose against each model's structure (the
//     tracks triangulated with the model's poses; image_registration.h) and joins the models
//     whose registration CheckRegistration accepts;
//   - two models that then share enough points are merged by the similarity those points
//     give (model_merging.h), the smaller mapped into the larger's frame; two that share too
//     few points to judge one, by the similarity the verified pairs between them give when
//     those pairs agree (pair_alignment.h);
// in rounds until no image joins and no models merge: a joined image triangulates new tracks,
// which may place the next one. An image left in two models that did not merge stays in the
// larger. PointlessMapper then adjusts every model that changed again (local Hessians,
// pointless global BA, triangulation) with its joined images.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "averaging/global_init.h"
#include "mapper/image_registration.h"
#include "mapper/model_merging.h"
#include "mapper/pair_alignment.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"
#include "pgba/util/json_fields.h"

namespace pgba {

struct ComponentJoiningOptions {
  // Images in no model tried by absolute pose against each model's points.
  bool join_images = true;
  // Models merged where they share points or verified pairs.
  bool merge_models = true;
  ImageRegistrationOptions registration;
  ModelAlignmentOptions alignment;  // merging by shared points
  PairAlignmentOptions pairs;       // merging by verified pairs, when too few points are shared
  int max_rounds = 10;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc).
  std::string Check() const;
};
// Config section "components": the keys a user sets (the others keep their defaults).
template <class Visit>
void JsonFields(ComponentJoiningOptions& o, Visit&& visit) {
  visit("join_images", o.join_images);
  visit("min_correspondences", o.registration.min_correspondences);
  visit("min_pose_inliers", o.registration.absolute_pose.min_inliers);
  visit("pose_threshold_px", o.registration.absolute_pose.threshold_px);
  visit("min_inlier_ratio", o.registration.min_inlier_ratio);
  visit("max_pair_rotation_deg", o.registration.max_pair_rotation_deg);
  visit("merge_models", o.merge_models);
  visit("min_shared_points", o.alignment.min_shared_points);
  visit("min_merge_pairs", o.pairs.min_pairs);
  visit("min_agreeing_pairs_ratio", o.pairs.min_agreeing_ratio);
  visit("max_merge_rotation_deg", o.pairs.max_rotation_deg);
  visit("max_merge_direction_deg", o.pairs.max_direction_deg);
  visit("max_rounds", o.max_rounds);
}
PGBA_JSON_FROM_FIELDS(ComponentJoiningOptions)

struct ModelMergeRecord {
  std::vector<std::string> into;  // the larger model's images before the merge, by name
  std::vector<std::string> from;  // the merged model's images
  ModelAlignment alignment;
};

struct ComponentJoiningResult {
  // Images joined by absolute pose (their registration in the model they ended in).
  std::map<uint32_t, AbsoluteRegistration> joined;
  // Images in no model at the end: why the last attempt failed.
  std::map<uint32_t, std::string> not_joined;
  std::vector<ModelMergeRecord> merges;
  int rounds = 0;

  // {"rounds", "joined": [{image, ...}], "not_joined": [{image, reason}], "merges": [...]}.
  nlohmann::json ToJson(const Reconstruction& tracks) const;
};

// `models`: the components' models (their poses the adjusted ones), updated in place (images
// joined, models merged and removed), largest first at the end; each model's images_dropped
// and dropped_image_ids list the images of `tracks` it does not hold. `tracks` with the
// cameras of the mapper; `pairs`: the verified pairs.
ComponentJoiningResult JoinComponents(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                                      const ComponentJoiningOptions& options, std::vector<GlobalInitResult>* models);

}  // namespace pgba
