// pgba's own SIFT (features.sift.implementation "pgba"): the algorithm of OpenCV's and
// VLFeat's SIFT (scale space, DoG extrema, orientations, 4x4x8 descriptors; sift_*.h) with
// the work inside one image parallel: OpenCV 4.6 blurs its 25 MP upsampled first octave on
// one thread. Through the whole pipeline pgba's takes 0.55-0.57x of OpenCV's CPU time on the
// Strecha photos (bench/front_end_speed.sh, docs/benchmarks.md "Front-end speed").
// Output in OpenCV's conventions (cv::KeyPoint, float descriptors) so ExtractSift treats
// both implementations alike; deterministic and independent of the number of threads.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace pgba {

struct PgbaSiftParams {
  bool upsample = true;  // first octave -1 (scale space on the doubled image)
  double contrast_threshold = 0.02;
  double edge_threshold = 10.0;
  int max_features = 0;  // keep the strongest; <= 0 keeps all
};

// gray: CV_8UC1. Keypoints as OpenCV 4.6's SIFT reports them: pt in input pixels with
// centres at integers, mapped from the doubled image by u / 2 (so the same +0.25 px bias
// as OpenCV when upsample is true, none otherwise), size = 2 sigma, angle in degrees,
// response = |DoG| at the extremum; strongest first. descriptors: one CV_32F row each.
void DetectAndDescribePgbaSift(const cv::Mat& gray, const PgbaSiftParams& params, std::vector<cv::KeyPoint>* keypoints,
                               cv::Mat* descriptors);

}  // namespace pgba
