// Fuzz target: the JSON readers of user files, a config (every section of every command,
// mapper/run_pipeline.h LoadRunOptions: schema, types, enum names, ranges) and a JSON
// calibration (pgba/io/calibration_json.h). The first byte chooses the reader.
#include <fstream>
#include <sstream>

#include "mapper/run_pipeline.h"
#include "pgba/io/calibration_json.h"
#include "tests/fuzz/fuzz_support.h"

namespace pgba::fuzz {

std::vector<std::string> Seeds() {
  std::vector<std::string> seeds = {
      std::string("C") + R"({"local_hessian": {"huber_px": 1.5, "attenuation_q": 10}, "global_ba": {"weighting": "hessian", "max_rounds": 3}})",
      std::string("C") + R"({"matching": {"pairs": {"method": "sequential", "window": 8, "loop": true}}, "local_motions": {"views": 7, "neighbour_strides": [1, 2]}})",
      std::string("C") + R"({"triplets": {"outlier_threshold_px": 4, "bundle_adjuster": {"loss": "cauchy"}}, "gcp": {"default_sigma": 0.1}})",
      std::string("K") + R"({"cameras": [{"camera_id": 1, "model": "PINHOLE", "width": 640, "height": 480, "params": [500, 501, 320, 240]},
          {"camera_id": 2, "model": "SIMPLE_RADIAL", "width": 320, "height": 240, "params": [250, 160, 120, -0.05]}],
          "images": {"a.png": 1, "b.png": 2}})"};
  // The presets of configs/, as shipped.
  for (const char* preset : {"aerial", "default", "longfocal", "object_ring", "video"}) {
    std::ifstream in(std::string(PGBA_SOURCE_DIR) + "/configs/" + preset + ".json");
    std::stringstream ss;
    ss << in.rdbuf();
    seeds.push_back("C" + ss.str());
  }
  return seeds;
}

}  // namespace pgba::fuzz

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pgba;
  if (size == 0) return 0;
  const bool as_calibration = (data[0] & 8) != 0;  // seeds: 'K' (0x4b) calibration, 'C' (0x43) config
  const std::string path =
      fuzz::WriteScratchFile(as_calibration ? "calib.json" : "config.json", fuzz::Bytes(data + 1, size - 1));
  fuzz::ExpectValueOrInputError(path, [&] {
    if (as_calibration) {
      const CalibrationFile f = ReadCalibrationJson(path);
      for (const auto& [id, cam] : f.cameras) fuzz::Require(cam.Validate().empty(), "accepted an invalid camera");
    } else {
      LoadRunOptions(path);
    }
  });
  return 0;
}
