#include "pgba/io/eth3d_slam.h"

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <tuple>
#include <algorithm>

#include "pgba/io/image_header.h"
#include "pgba/io/input_checks.h"
#include "pgba/util/error.h"
#include "pgba/util/input_file.h"
#include "pgba/util/logging.h"
#include "pgba/util/text_reader.h"

namespace pgba {

namespace fs = std::filesystem;

namespace {

// The model, and each image's photo path (`sources`, by name).
Reconstruction ReadSequence(const std::string& sequence_dir, const Eth3dSlamOptions& options,
                            std::map<std::string, std::string>* sources) {
  const fs::path dir(sequence_dir);
  std::vector<std::string> tok;

  std::map<double, Pose> gt;  // by timestamp
  {
    TextReader r((dir / "groundtruth.txt").string());
    while (r.NextLine(&tok)) {
      if (tok.size() != 8) r.Fail("expected 'timestamp tx ty tz qx qy qz qw', got " + std::to_string(tok.size()) + " fields");
      double v[8];
      for (int i = 0; i < 8; ++i) v[i] = r.ToDouble(tok[i], "ground-truth value");
      const Eigen::Quaterniond q_wc(v[7], v[4], v[5], v[6]);
      if (std::abs(q_wc.norm() - 1.0) > 1e-3) r.Fail("quaternion is not unit");
      gt[v[0]] = Pose::FromRC(q_wc.normalized().toRotationMatrix().transpose(), Eigen::Vector3d(v[1], v[2], v[3]));
    }
  }
  if (gt.empty()) ThrowInputError((dir / "groundtruth.txt").string(), 0, "no ground-truth line");

  Reconstruction rec;
  Camera cam;
  cam.camera_id = 1;
  cam.model = CameraModel::kPinhole;
  {
    TextReader r((dir / "calibration.txt").string());
    if (!r.NextLine(&tok) || tok.size() != 4) r.Fail("expected 'fx fy cx cy'");
    for (const std::string& t : tok) cam.params.push_back(r.ToDouble(t, "calibration value"));
  }

  TextReader r((dir / "rgb.txt").string());
  uint32_t next_id = 1;
  while (r.NextLine(&tok)) {
    if (tok.size() != 2) r.Fail("expected 'timestamp rgb/FILE', got " + std::to_string(tok.size()) + " fields");
    const double t = r.ToDouble(tok[0], "timestamp");
    // Nearest ground-truth timestamp.
    auto it = gt.lower_bound(t);
    if (it == gt.end() || (it != gt.begin() && t - std::prev(it)->first < it->first - t)) it = std::prev(it);
    if (std::abs(it->first - t) > options.max_dt_s) {
      PGBA_LOG_WARN << FormatInputError(r.path(), r.line_number(), "frame " + tok[1] + " has no ground truth; left out");
      continue;
    }
    if (cam.width == 0) std::tie(cam.width, cam.height) = ReadImageSize((dir / tok[1]).string());
    Image im;
    im.image_id = next_id++;
    im.name = fs::path(tok[1]).filename().string();
    im.camera_id = 1;
    im.pose = it->second;
    if (!sources->emplace(im.name, (dir / tok[1]).string()).second) r.Fail("frame " + im.name + " listed twice");
    rec.images[im.image_id] = im;
  }
  if (rec.images.empty()) ThrowInputError(r.path(), 0, "no frame with ground truth");
  if (const std::string problem = CheckCamera(cam); !problem.empty())
    ThrowInputError((dir / "calibration.txt").string(), 0, problem + " (the size is the first photo's)");
  rec.cameras[1] = cam;
  return rec;
}

}  // namespace

Reconstruction ReadEth3dSlamGroundTruth(const std::string& sequence_dir, const Eth3dSlamOptions& options) {
  std::map<std::string, std::string> sources;
  return ReadSequence(sequence_dir, options, &sources);
}

size_t ConvertEth3dSlamSequence(const std::string& sequence_dir, const std::string& out,
                                const Eth3dSlamOptions& options) {
  std::map<std::string, std::string> sources;
  const Reconstruction gt = ReadSequence(sequence_dir, options, &sources);
  WriteDatasetLayout(gt, sources, out, options.layout);
  return gt.images.size();
}

}  // namespace pgba
