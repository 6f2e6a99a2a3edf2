// COLMAP text model: cameras.txt, images.txt, points3D.txt.
//
// Reading is strict: a truncated line, a non-number, NaN/Inf, a duplicate id or an id that
// does not resolve raises InputError("FILE:LINE: problem"). Writing uses 17 significant
// digits, so read -> write -> read reproduces every value bit for bit, and goes through a
// staging directory so that a model directory is never left half-written.
#pragma once

#include <map>
#include <string>

#include "pgba/scene/reconstruction.h"

namespace pgba {

// cameras.txt alone (a calibration file).
//
// Camera::has_prior_focal_length, which COLMAP's text format has no field for, travels in a
// comment COLMAP ignores, written only when some camera lacks a prior focal:
//   # pgba: no prior focal length: CAMERA_ID...
// (every listed id must be a camera of the file); cameras not listed have a prior.
std::map<uint32_t, Camera> ReadColmapCameras(const std::string& path);

// Reads DIR/{cameras,images,points3D}.txt. A missing points3D.txt is an error unless
// `points_optional` (ground-truth models often ship poses only).
Reconstruction ReadColmapText(const std::string& dir, bool points_optional = false);

// Writes DIR/{cameras,images,points3D}.txt atomically (the whole directory is swapped in).
void WriteColmapText(const Reconstruction& rec, const std::string& dir);

// Single-file writers used by WriteColmapText (exposed for tests and partial exports).
void WriteColmapCamerasFile(const Reconstruction& rec, const std::string& path);
void WriteColmapImagesFile(const Reconstruction& rec, const std::string& path);
void WriteColmapPointsFile(const Reconstruction& rec, const std::string& path);

}  // namespace pgba
