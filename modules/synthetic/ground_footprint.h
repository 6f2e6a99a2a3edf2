// Ground footprints of nadir-ish images and their overlap: an independent truth of which
// images of an aerial block see common ground, computed from the true poses alone (no
// features, no rendering), for judging pair selection (which pairs retrieval should find).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "pgba/geometry/pose.h"
#include "pgba/scene/camera.h"

namespace pgba::synthetic {

// Convex polygon in the ground plane, counter-clockwise.
using GroundPolygon = std::vector<Eigen::Vector2d>;

// Where the four image corners' rays meet the plane z = ground_z; empty if a corner ray
// does not reach it (points at or above the horizon). Distortion moves the corners only
// slightly inwards or outwards; the corners' rays are exact for the camera's own model.
GroundPolygon GroundFootprint(const Camera& camera, const Pose& pose, double ground_z);

double PolygonArea(const GroundPolygon& polygon);

// Intersection of two convex polygons (Sutherland-Hodgman clipping of `a` by `b`'s edges).
GroundPolygon IntersectConvex(const GroundPolygon& a, const GroundPolygon& b);

// Area of the intersection over the smaller footprint's area, in [0, 1]; 0 if either is
// empty. A pair of images "overlaps" for pair selection when this is large enough that
// features can be matched between them.
double FootprintOverlap(const GroundPolygon& a, const GroundPolygon& b);

}  // namespace pgba::synthetic
