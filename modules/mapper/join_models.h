// PointlessMapper's step 10 (pointless_mapper.h) as a stage of its report: the adjusted models
// continued from their adjusted poses by what connects them (JoinComponents, components.h),
// and the start of a model's next adjustment from its adjusted poses (also step 8's
// re-adjustment).
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "averaging/global_init.h"
#include "mapper/components.h"
#include "mapper/pointless_mapper.h"
#include "pgba/geometry/pose.h"
#include "pgba/io/report.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

// A model's adjusted poses as the start of its next adjustment: its initialisation with the
// final poses (images the BA left out removed with their triplets).
GlobalInitResult AdjustedStart(const GlobalInitResult& init, const std::map<uint32_t, Pose>& poses);

// Step 10: the images left out joined by absolute pose against the adjusted models' points, the
// models merged where they share points or verified pairs (components.h), timed as stage
// "components". Returns the models to adjust again (empty when nothing changed).
std::vector<GlobalInitResult> JoinModels(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                                         const ComponentJoiningOptions& options, const PointlessMapperResult& r,
                                         Report* report, ComponentJoiningResult* joining);

}  // namespace pgba
