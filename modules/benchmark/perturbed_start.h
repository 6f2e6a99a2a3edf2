// A start moved away from the initialisation, for validation on starts the defaults were not
// chosen on (`pgba benchmark --perturb-deg`): every pose rotated by exactly `deg` degrees
// about a random axis and its centre moved by deg (in radians) times the distance to its
// nearest other centre (a baseline: the same angular size as the rotation, seen from a
// neighbour). The relative rotation of two poses then moves by about sqrt(2) deg.
// Deterministic for a seed.
#pragma once

#include <cstdint>
#include <map>

#include "pgba/geometry/pose.h"

namespace pgba {

std::map<uint32_t, Pose> PerturbedStart(const std::map<uint32_t, Pose>& poses, double deg, uint64_t seed);

}  // namespace pgba
