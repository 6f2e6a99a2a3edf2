// Calibration as JSON, the alternative to a COLMAP cameras.txt for `pgba run --calib`:
//
//   {"cameras": [{"camera_id": 1, "model": "PINHOLE", "width": 3072, "height": 2048,
//                 "params": [2759.48, 2764.16, 1520.69, 1006.81]}],
//    "images": {"0000.jpg": 1, "0001.jpg": 1}}
//
// "model" and "params" follow COLMAP's camera models (cameras.txt, same parameter order);
// "images" (optional) says which image uses which camera, as a --camera-map file does, and
// is needed only with several cameras. Chosen by the file's extension (.json).
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "pgba/scene/camera.h"

namespace pgba {

struct CalibrationFile {
  std::map<uint32_t, Camera> cameras;
  std::map<std::string, uint32_t> camera_of;  // from "images"; empty if absent
};

// InputError "FILE: where: problem" for unparsable JSON, a missing or mistyped key, an
// unknown model, a duplicate camera id, a camera that fails Camera::Validate, or an image
// mapped to a camera that is not listed.
CalibrationFile ReadCalibrationJson(const std::string& path);

}  // namespace pgba
