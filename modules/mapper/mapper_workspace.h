// The PointlessMapper's artefacts on disk (docs/formats.md, "The workspace"): what each step
// writes, and the reading back that lets a re-run start after them.
//   steps 1-4: pairs.json, triplets.json (kept triplets with their similarities), init/
//   step 5:    motions.json (the relative motions as linearised), local_hessians.json
//   step 8:    sparse/0/, sparse/1/, ... (every model, largest first, as COLMAP text with its
//              points.ply), and the largest model again as sparse/ and points.ply
#pragma once

#include <string>

#include "mapper/pointless_mapper.h"

namespace pgba {

// WS/pairs.json, WS/triplets.json and WS/init/ (COLMAP text model: the mapper's cameras, the
// initial poses, the points triangulated with them).
void WriteGlobalMapperWorkspace(const std::string& workspace, const Reconstruction& tracks,
                                const GlobalMapperResult& result);

// The artefacts of an earlier `init` or `reconstruct` in `workspace` (the largest model's: a
// re-run from a workspace adjusts that model alone, with the images joined to it): WS/pairs.json,
// WS/triplets.json and the initial poses of WS/init/ (matched to `tracks` by image name), and
// WS/motions.json with WS/local_hessians.json where present (stage "workspace" of `report`:
// nothing of steps 1-5 is estimated again). A missing or foreign artefact is an InputError
// naming the file.
PointlessMapperResult ReadMapperWorkspace(const Reconstruction& tracks, const std::string& workspace,
                                          const PointlessMapperOptions& options, Report* report);

// Step 5's artefacts: WS/motions.json and WS/local_hessians.json.
void WriteLocalHessianWorkspace(const std::string& workspace, const Reconstruction& tracks,
                                const PreparedHessians& hessians);

// The workspace of `init` (WriteGlobalMapperWorkspace), OUT/motions.json and
// OUT/local_hessians.json (the largest model's; unless the mapper wrote them already:
// PreparedHessians::released), OUT/sparse/N/ with OUT/sparse/N/points.ply for every model N
// (largest first), and the largest model as OUT/sparse/ and OUT/points.ply.
void WriteReconstruction(const std::string& out, const Reconstruction& tracks, const PointlessMapperResult& result);

}  // namespace pgba
