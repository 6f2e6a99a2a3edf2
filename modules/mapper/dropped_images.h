// The images a reconstruction left out, each with the stage that left it out in words a user
// can act on: the console's one warning line, report.json's "images_dropped_reason" and the
// reasons of its "image_fates".
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "mapper/pointless_mapper.h"

namespace pgba {

struct DroppedImage {
  std::string name;
  std::string reason;
};

// The images of `tracks` in no model of `result`, in name order, each with the first reason
// that applies: no track, no verified pair, dropped by a model's final verification, in no
// component of the triplet graph (with why absolute pose could not join it), its model not
// adjusted, left out by the global BA.
std::vector<DroppedImage> DroppedImages(const Reconstruction& tracks, const PointlessMapperResult& result);

// One line: how many of `num_images` were left out, their names grouped by reason, and what to
// try; "" when none was.
std::string DroppedImagesSummary(const std::vector<DroppedImage>& dropped, size_t num_images);

// Every image of `tracks` with its fate in `result`: {"image", "model" (index, or null),
// "registered_by" ("triplets", "absolute_pose"), "registered_again" (the failed check's reason),
// or "reason" (why in no model: `dropped`'s, the DroppedImages of `result`)}; report.json's
// "image_fates".
nlohmann::json ImageFates(const Reconstruction& tracks, const PointlessMapperResult& result,
                          const std::vector<DroppedImage>& dropped);

// {name: reason} in name order.
nlohmann::json DroppedImagesJson(const std::vector<DroppedImage>& dropped);

}  // namespace pgba
