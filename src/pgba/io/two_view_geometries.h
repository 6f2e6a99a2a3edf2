// Text file of verified two-view geometries (the image front end's output for the triplet
// stage), one pair per line:
//   IMAGE_ID1 IMAGE_ID2 QW QX QY QZ TX TY TZ NUM_INLIERS NUM_TRACKS MEDIAN_TRIANGULATION_ANGLE_DEG
// with (q, t) the relative pose x_2 = R_21 x_1 + t_21 (|t| = 1), Hamilton quaternion as
// COLMAP writes it. '#' lines are comments. Values are written with 17 significant digits.
#pragma once

#include <string>
#include <vector>

#include "pgba/scene/view_graph.h"

namespace pgba {

void WriteTwoViewGeometries(const std::vector<TwoViewGeometry>& geometries, const std::string& path);
// Strict: InputError "FILE:LINE: problem" on malformed lines or non-finite values.
std::vector<TwoViewGeometry> ReadTwoViewGeometries(const std::string& path);

}  // namespace pgba
