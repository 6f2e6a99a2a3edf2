#include "features/gaussian_blur.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "features/vec8.h"

namespace pgba {
namespace {

// Rows per task: large enough to amortise the scheduling, small enough to balance 2+ cores.
constexpr int kRowGrain = 16;
// Columns per strip of the vertical pass (a multiple of its 32-float step).
constexpr int kColumnStrip = 256;

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

// The row kernels (vec8.h): plain IEEE float multiplies and adds, one weight at a time over
// all x in a fixed order: every pixel gets the same bits on either path and for any split of
// the image into tasks.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"  // inline only: no vector crosses a call boundary
using simd::Load8;
using simd::Store8;
using simd::Vec8;

// out[x] = w0 rows[0][x0 + x] + sum_k w_k (rows[-k][x0 + x] + rows[+k][x0 + x]) for x in
// [0, n): the vertical pass of one output row over columns x0.., rows[k] pointing at source
// row y + k (reflected).
PGBA_MULTIVERSION
void VerticalRow(const float* const* rows, int x0, const float* w, int r, int n, float* __restrict out) {
  int x = 0;
  for (; x + 32 <= n; x += 32) {
    const Vec8 w0 = Vec8{} + w[0];
    const float* c = rows[0] + x0 + x;
    Vec8 s0 = w0 * Load8(c), s1 = w0 * Load8(c + 8), s2 = w0 * Load8(c + 16), s3 = w0 * Load8(c + 24);
    for (int k = 1; k <= r; ++k) {
      const Vec8 wk = Vec8{} + w[k];
      const float* a = rows[-k] + x0 + x;
      const float* b = rows[k] + x0 + x;
      s0 += wk * (Load8(a) + Load8(b));
      s1 += wk * (Load8(a + 8) + Load8(b + 8));
      s2 += wk * (Load8(a + 16) + Load8(b + 16));
      s3 += wk * (Load8(a + 24) + Load8(b + 24));
    }
    Store8(out + x, s0);
    Store8(out + x + 8, s1);
    Store8(out + x + 16, s2);
    Store8(out + x + 24, s3);
  }
  for (; x < n; ++x) {
    float s = w[0] * rows[0][x0 + x];
    for (int k = 1; k <= r; ++k) s += w[k] * (rows[-k][x0 + x] + rows[k][x0 + x]);
    out[x] = s;
  }
}

// out[x] = w0 p[x] + sum_k w_k (p[x - k] + p[x + k]) for x in [0, n) on a padded row; with
// dog, also dog[x] = out[x] - src_for_dog[x]. The same order of operations per pixel as the
// scalar tail, so every pixel gets the same bits whatever its column.
PGBA_MULTIVERSION
void HorizontalRow(const float* p, const float* w, int r, int n, float* __restrict out, const float* src_for_dog,
                   float* __restrict dog) {
  int x = 0;
  for (; x + 16 <= n; x += 16) {
    const Vec8 w0 = Vec8{} + w[0];
    Vec8 s0 = w0 * Load8(p + x), s1 = w0 * Load8(p + x + 8);
    for (int k = 1; k <= r; ++k) {
      const Vec8 wk = Vec8{} + w[k];
      s0 += wk * (Load8(p + x - k) + Load8(p + x + k));
      s1 += wk * (Load8(p + x + 8 - k) + Load8(p + x + 8 + k));
    }
    Store8(out + x, s0);
    Store8(out + x + 8, s1);
    if (dog != nullptr) {
      Store8(dog + x, s0 - Load8(src_for_dog + x));
      Store8(dog + x + 8, s1 - Load8(src_for_dog + x + 8));
    }
  }
  for (; x < n; ++x) {
    float s = w[0] * p[x];
    for (int k = 1; k <= r; ++k) s += w[k] * (p[x - k] + p[x + k]);
    out[x] = s;
    if (dog != nullptr) dog[x] = s - src_for_dog[x];
  }
}
#pragma GCC diagnostic pop

}  // namespace

void ParallelGaussianBlur(const cv::Mat& src, cv::Mat& dst, double sigma, cv::Mat* dog) {
  CV_Assert(src.type() == CV_32F && src.data != dst.data);
  const int rows = src.rows, cols = src.cols;
  const std::vector<float> w = HalfKernel(sigma);
  const int r = static_cast<int>(w.size()) - 1;
  dst.create(rows, cols, CV_32F);
  if (dog != nullptr) {
    CV_Assert(dog->data != src.data && dog->data != dst.data);
    dog->create(rows, cols, CV_32F);
  }
  tbb::parallel_for(tbb::blocked_range<int>(0, rows, kRowGrain), [&](const tbb::blocked_range<int>& range) {
    const int y0 = range.begin(), ny = range.end() - range.begin();
    // Source rows y0 - r .. y0 + ny - 1 + r (reflected): src_rows[y - y0 + r + k] is row y + k.
    std::vector<const float*> src_rows(ny + 2 * r);
    for (int i = 0; i < ny + 2 * r; ++i) src_rows[i] = src.ptr<float>(Reflect101(y0 - r + i, rows));
    // The vertical pass of the task's rows, a strip of columns at a time: the strip's
    // ny + 2r source rows stay in L1 from one output row to the next (whole rows of the
    // upsampled octave, 24 KB each, did not). Each row padded by r on both sides.
    const int stride = cols + 2 * r;
    thread_local std::vector<float> vertical;  // grown once per thread, not per task
    if (vertical.size() < static_cast<size_t>(ny) * stride) vertical.resize(static_cast<size_t>(ny) * stride);
    for (int x0 = 0; x0 < cols; x0 += kColumnStrip) {
      const int n = std::min(kColumnStrip, cols - x0);
      for (int t = 0; t < ny; ++t)
        VerticalRow(src_rows.data() + t + r, x0, w.data(), r, n, &vertical[static_cast<size_t>(t) * stride + r + x0]);
    }
    for (int t = 0; t < ny; ++t) {
      float* pad = &vertical[static_cast<size_t>(t) * stride];
      const float* col = pad + r;
      for (int x = 0; x < r; ++x) {
        pad[x] = col[Reflect101(x - r, cols)];
        pad[cols + r + x] = col[Reflect101(cols + x, cols)];
      }
      const int y = y0 + t;
      HorizontalRow(col, w.data(), r, cols, dst.ptr<float>(y), src.ptr<float>(y),
                    dog != nullptr ? dog->ptr<float>(y) : nullptr);
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
