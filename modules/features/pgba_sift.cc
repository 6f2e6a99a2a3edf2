#include "features/pgba_sift.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>

#include "features/sift_descriptor.h"
#include "features/sift_keypoints.h"
#include "features/sift_scale_space.h"
#include "pgba/util/logging.h"
#include "pgba/util/timer.h"

namespace pgba {

void DetectAndDescribePgbaSift(const cv::Mat& gray, const PgbaSiftParams& params, std::vector<cv::KeyPoint>* keypoints,
                               cv::Mat* descriptors) {
  CV_Assert(gray.type() == CV_8UC1);
  Timer timer;  // stage times in the debug log: where the time of one image goes
  SiftDetectionOptions detection;
  detection.contrast_threshold = params.contrast_threshold;
  detection.edge_threshold = params.edge_threshold;
  detection.max_features = params.max_features;
  // Each octave's extrema as soon as it is built: its detection-only layers then make room
  // for the next octaves (sift_scale_space.h).
  std::vector<SiftExtremum> extrema;
  double t_extrema = 0;
  const SiftScaleSpace ss = BuildSiftScaleSpace(gray, params.upsample, [&](const SiftScaleSpace& s, int octave) {
    const double t0 = timer.Seconds();
    FindSiftExtrema(s, octave, detection, &extrema);
    t_extrema += timer.Seconds() - t0;
  });
  const double t_pyramid = timer.Seconds() - t_extrema;
  const std::vector<SiftKeypoint> found = OrientSiftExtrema(ss, extrema, detection);
  const double t_detect = timer.Seconds();

  // Octave pixels -> input pixels (the doubled image's pixels are half an input pixel).
  const float to_input = params.upsample ? 0.5f : 1.f;
  std::vector<cv::KeyPoint> all(found.size());
  for (size_t i = 0; i < found.size(); ++i) {
    const SiftKeypoint& k = found[i];
    const float f = static_cast<float>(1 << k.octave) * to_input;
    all[i] = cv::KeyPoint(k.x * f, k.y * f, 2 * k.sigma * f, k.angle, k.response, k.octave);
  }
  // Strongest first, a total order (ties by position, size, angle), then the cap: only
  // the kept keypoints get a descriptor.
  std::vector<int> order(all.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const cv::KeyPoint &ka = all[a], &kb = all[b];
    if (ka.response != kb.response) return ka.response > kb.response;
    if (ka.pt.y != kb.pt.y) return ka.pt.y < kb.pt.y;
    if (ka.pt.x != kb.pt.x) return ka.pt.x < kb.pt.x;
    if (ka.size != kb.size) return ka.size < kb.size;
    if (ka.angle != kb.angle) return ka.angle < kb.angle;
    return a < b;
  });
  if (params.max_features > 0 && static_cast<int>(order.size()) > params.max_features)
    order.resize(params.max_features);

  keypoints->resize(order.size());
  descriptors->create(static_cast<int>(order.size()), kSiftCells * kSiftCells * kSiftOrientations, CV_32F);
  // Descriptors computed in the keypoints' order in the scale space (found's: octave, layer,
  // row), each into its row of the output: neighbouring windows share cache lines, where
  // the response order jumped across a 100 MB layer for every window (perf: a quarter of the
  // descriptor time waited on the image rows). Each descriptor is independent of the order.
  std::vector<int> by_position(order.begin(), order.end());
  std::sort(by_position.begin(), by_position.end());
  std::vector<int> row_of(all.size(), -1);
  for (size_t i = 0; i < order.size(); ++i) row_of[order[i]] = static_cast<int>(i);
  tbb::parallel_for(size_t(0), by_position.size(), [&](size_t t) {
    const int k = by_position[t];
    const int i = row_of[k];
    (*keypoints)[i] = all[k];
    ComputeSiftDescriptor(ss, found[k], descriptors->ptr<float>(i));
  });
  PGBA_LOG_DEBUG << "pgba sift " << gray.cols << "x" << gray.rows << ": pyramid+DoG " << t_pyramid << " s, extrema+"
                 << "orientation " << t_detect - t_pyramid << " s (" << found.size() << " keypoints), descriptors "
                 << timer.Seconds() - t_detect << " s (" << order.size() << ")";
}

}  // namespace pgba
