#include "features/gaussian_blur.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace pgba {
namespace {

// Rows per task: large enough to amortise the scheduling, small enough to balance 2+ cores.
constexpr int kRowGrain = 16;

// Reflect-101 index into [0, n): ... 2 1 | 0 1 2 ... n-1 | n-2 ...
inline int Reflect101(int i, int n) {
  if (n == 1) return 0;
  while (i < 0 || i >= n) i = i < 0 ? -i : 2 * (n - 1) - i;
  return i;
}

// Half of a normalised Gaussian kernel: w[0] the centre, w[k] the weight at +-k.
std::vector<float> HalfKernel(double sigma) {
  const int ksize = std::max(1, static_cast<int>(std::lround(sigma * 8 + 1)) | 1);
  const int r = ksize / 2;
  std::vector<double> w(r + 1);
  double sum = 0;
  for (int k = 0; k <= r; ++k) {
    w[k] = std::exp(-0.5 * k * k / (sigma * sigma));
    sum += k == 0 ? w[k] : 2 * w[k];
  }
  std::vector<float> out(r + 1);
  for (int k = 0; k <= r; ++k) out[k] = static_cast<float>(w[k] / sum);
  return out;
}

// out[x] = w0 p[x] + sum_k w_k (p[x - k stride] + p[x + k stride]) for x in [0, n): the
// horizontal pass with stride 1 on a padded row, the vertical one with the row stride.
// One weight at a time over all x: the compiler vectorises it without reassociating a sum,
// so every pixel gets the same float operations in the same order.
void AccumulateSymmetric(const float* p, ptrdiff_t stride, const std::vector<float>& w, int n,
                         float* __restrict out) {
  const float w0 = w[0];
  for (int x = 0; x < n; ++x) out[x] = w0 * p[x];
  for (size_t k = 1; k < w.size(); ++k) {
    const float wk = w[k];
    const float* __restrict a = p - static_cast<ptrdiff_t>(k) * stride;
    const float* __restrict b = p + static_cast<ptrdiff_t>(k) * stride;
    for (int x = 0; x < n; ++x) out[x] += wk * (a[x] + b[x]);
  }
}

}  // namespace

void ParallelGaussianBlur(const cv::Mat& src, cv::Mat& dst, double sigma) {
  CV_Assert(src.type() == CV_32F && src.data != dst.data);
  const int rows = src.rows, cols = src.cols;
  const std::vector<float> w = HalfKernel(sigma);
  const int r = static_cast<int>(w.size()) - 1;
  cv::Mat tmp(rows, cols, CV_32F);
  dst.create(rows, cols, CV_32F);
  // Horizontal pass into tmp. The inner loops run over x with one weight at a time, so
  // the compiler vectorises them without reassociating any sum.
  tbb::parallel_for(tbb::blocked_range<int>(0, rows, kRowGrain), [&](const tbb::blocked_range<int>& range) {
    std::vector<float> pad(cols + 2 * r);
    for (int y = range.begin(); y < range.end(); ++y) {
      const float* s = src.ptr<float>(y);
      std::copy(s, s + cols, pad.data() + r);
      for (int x = 0; x < r; ++x) {
        pad[x] = s[Reflect101(x - r, cols)];
        pad[cols + r + x] = s[Reflect101(cols + x, cols)];
      }
      AccumulateSymmetric(pad.data() + r, 1, w, cols, tmp.ptr<float>(y));
    }
  });
  // Vertical pass: each output row is a weighted sum of whole tmp rows.
  tbb::parallel_for(tbb::blocked_range<int>(0, rows, kRowGrain), [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y < range.end(); ++y) {
      if (y >= r && y + r < rows) {
        AccumulateSymmetric(tmp.ptr<float>(y), static_cast<ptrdiff_t>(tmp.step1()), w, cols, dst.ptr<float>(y));
        continue;
      }
      float* __restrict d = dst.ptr<float>(y);
      const float* __restrict c = tmp.ptr<float>(y);
      for (int x = 0; x < cols; ++x) d[x] = w[0] * c[x];
      for (int k = 1; k <= r; ++k) {
        const float wk = w[k];
        const float* __restrict a = tmp.ptr<float>(Reflect101(y - k, rows));
        const float* __restrict b = tmp.ptr<float>(Reflect101(y + k, rows));
        for (int x = 0; x < cols; ++x) d[x] += wk * (a[x] + b[x]);
      }
    }
  });
}

void ParallelUpsample2x(const cv::Mat& src8u, cv::Mat& dst) {
  CV_Assert(src8u.type() == CV_8UC1);
  const int rows = src8u.rows, cols = src8u.cols;
  dst.create(2 * rows, 2 * cols, CV_32F);
  // Horizontal doubling of input row y into out (2 cols floats): even outputs lean on the
  // left neighbour, odd ones on the right one, 3:1.
  auto double_row = [cols](const uint8_t* s, float* out) {
    for (int x = 0; x < cols; ++x) {
      const float c = s[x], l = s[std::max(x - 1, 0)], rt = s[std::min(x + 1, cols - 1)];
      out[2 * x] = 0.75f * c + 0.25f * l;
      out[2 * x + 1] = 0.75f * c + 0.25f * rt;
    }
  };
  tbb::parallel_for(tbb::blocked_range<int>(0, rows, kRowGrain / 2), [&](const tbb::blocked_range<int>& range) {
    std::vector<float> above(2 * cols), centre(2 * cols), below(2 * cols);
    for (int y = range.begin(); y < range.end(); ++y) {
      double_row(src8u.ptr<uint8_t>(std::max(y - 1, 0)), above.data());
      double_row(src8u.ptr<uint8_t>(y), centre.data());
      double_row(src8u.ptr<uint8_t>(std::min(y + 1, rows - 1)), below.data());
      float* even = dst.ptr<float>(2 * y);
      float* odd = dst.ptr<float>(2 * y + 1);
      for (int x = 0; x < 2 * cols; ++x) {
        even[x] = 0.75f * centre[x] + 0.25f * above[x];
        odd[x] = 0.75f * centre[x] + 0.25f * below[x];
      }
    }
  });
}

void ParallelDecimate2x(const cv::Mat& src, cv::Mat& dst) {
  CV_Assert(src.type() == CV_32F && src.data != dst.data);
  dst.create(src.rows / 2, src.cols / 2, CV_32F);
  tbb::parallel_for(tbb::blocked_range<int>(0, dst.rows, kRowGrain), [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y < range.end(); ++y) {
      const float* s = src.ptr<float>(2 * y);
      float* d = dst.ptr<float>(y);
      for (int x = 0; x < dst.cols; ++x) d[x] = s[2 * x];
    }
  });
}

}  // namespace pgba
