// Withheld loop correspondences (docs/formats.md, "Inputs"): one line per
// correspondence, `name_i x_i y_i name_j x_j y_j`, pixels. These are matches between images
// whose connection was removed from the tracks (e.g. the two ends of a closed ring); the
// loop-closure metric triangulates them from the two final poses.
//
// Reading is strict: every non-comment line has exactly six fields, finite coordinates and
// two different image names; anything else is an InputError "FILE:LINE: problem". Names
// must not contain whitespace (the format is whitespace separated), so the writer refuses
// them rather than write a file it could not read back.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace pgba {

// A withheld correspondence between two images (pixels), for the loop-closure metric.
struct LoopCorrespondence {
  std::string name_i;
  Eigen::Vector2d xy_i = Eigen::Vector2d::Zero();
  std::string name_j;
  Eigen::Vector2d xy_j = Eigen::Vector2d::Zero();
};

std::vector<LoopCorrespondence> ReadLoopPairs(const std::string& path);

// Writes atomically (temporary file + rename), 17 significant digits (exact round trip).
void WriteLoopPairs(const std::vector<LoopCorrespondence>& pairs, const std::string& path);

}  // namespace pgba
