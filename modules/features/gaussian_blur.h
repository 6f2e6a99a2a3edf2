// Float image filters of the SIFT scale space, parallelised inside one image with TBB: a
// 6 MP photo's upsampled first octave is 25 MP per layer, and OpenCV 4.6 blurs it on one
// thread. Every output pixel is computed by the same sequence of float operations whatever
// the split into chunks, so the results are byte-identical for any thread count.
#pragma once

#include <opencv2/core.hpp>

namespace pgba {

// Separable Gaussian blur of a CV_32F image (kernel radius round(4 sigma) as OpenCV's for
// float images, borders reflected without repeating the edge pixel as OpenCV's default).
// dst may not alias src. One pass over the image: each output row is the vertical sum of its
// 2r + 1 source rows (cache-resident) into a row buffer, then the horizontal sum of that
// buffer, 8 floats at a time; no full-size intermediate image is written. With
// dog, also dog = dst - src, computed while the row is in cache (the DoG layer of SIFT).
// The inner loops are compiled for AVX2 as well as the baseline and chosen at run time;
// neither uses FMA, so both give the same bits.
void ParallelGaussianBlur(const cv::Mat& src, cv::Mat& dst, double sigma, cv::Mat* dog = nullptr);

// 8-bit image -> CV_32F image of twice the size, bilinear: output pixel u samples the input
// at u/2 - 0.25 (pixel centres at integers; the same grid as OpenCV's INTER_LINEAR_EXACT
// doubling, so callers map keypoints back the same way), edges replicated.
void ParallelUpsample2x(const cv::Mat& src8u, cv::Mat& dst);

// Every second pixel (dst(y, x) = src(2y, 2x)), size (cols/2, rows/2): the next octave's
// first layer, whose blur is exactly twice the sigma of the layer it is taken from.
void ParallelDecimate2x(const cv::Mat& src, cv::Mat& dst);

}  // namespace pgba
