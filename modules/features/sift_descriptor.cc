#include "features/sift_descriptor.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <vector>

#include "features/gradient_polar.h"
#include "features/separable_gaussian.h"

namespace pgba {
namespace {

constexpr float kCellWidth = 3.f;    // one cell spans 3 keypoint sigmas
constexpr float kClip = 0.2f;        // Lowe's clipping of large gradient bins
constexpr float kOutputNorm = 512.f;

// floor() of a float of moderate size, exactly, without the libm call of the SSE2 baseline.
inline int FloorInt(float v) {
  const int t = static_cast<int>(v);
  return t - (static_cast<float>(t) > v ? 1 : 0);
}

// A descriptor window's samples (thread-local, grown to the largest window): gradients,
// weights, angles and magnitudes, and each sample's position in cell units.
struct DescriptorSamples {
  GradientSamples gradient;
  std::vector<float> rbin, cbin;
  void Reserve(int n) {
    gradient.Reserve(n);
    if (rbin.size() < gradient.dx.size()) {
      rbin.resize(gradient.dx.size());
      cbin.resize(gradient.dx.size());
    }
  }
};

}  // namespace

void ComputeSiftDescriptor(const SiftScaleSpace& ss, const SiftKeypoint& kp, float* out) {
  constexpr int d = kSiftCells, n = kSiftOrientations;
  const cv::Mat& img = ss.gaussians[kp.octave][kp.layer];
  const int px = static_cast<int>(std::lround(kp.x)), py = static_cast<int>(std::lround(kp.y));
  // The window rotates with the keypoint; kp.angle is OpenCV's (360 - gradient angle).
  float angle = 360.f - kp.angle;
  if (std::abs(angle - 360.f) < FLT_EPSILON) angle = 0.f;
  const float rad = angle * static_cast<float>(CV_PI / 180.0);
  const float hist_width = kCellWidth * kp.sigma;
  int radius = static_cast<int>(std::lround(hist_width * 1.4142135623730951f * (d + 1) * 0.5f));
  radius = std::min(radius, static_cast<int>(std::sqrt(double(img.cols) * img.cols + double(img.rows) * img.rows)));
  const float cos_t = std::cos(rad) / hist_width, sin_t = std::sin(rad) / hist_width;
  const float bins_per_degree = n / 360.f;
  const float exp_scale = -1.f / (d * d * 0.5f);
  // The Gaussian weight depends on the rotated offset's length only, which is the unrotated
  // one's: exp(-(i^2 + j^2) / (hist_width^2 d^2 / 2)) = g[i] g[j], one exp per offset
  // instead of one per sample.
  const SeparableGaussian g(radius, exp_scale / (hist_width * hist_width));

  // The window's samples in row-major order (the order of the histogram sums): gradient,
  // Gaussian weight and bin coordinates of those inside the rotated 4 x 4 cells; then their
  // angles and magnitudes 8 at a time (GradientsToPolar: the same float operations as one at
  // a time, so the same bits); then the trilinear spread, one sample after the other.
  thread_local DescriptorSamples w;
  w.Reserve((2 * radius + 1) * (2 * radius + 1));
  int m = 0;
  for (int i = -radius; i <= radius; ++i) {
    const int r = py + i;
    if (r <= 0 || r >= img.rows - 1) continue;
    const float* row = img.ptr<float>(r);
    const float* up = img.ptr<float>(r - 1);
    const float* down = img.ptr<float>(r + 1);
    const float gi = g[std::abs(i)];
    for (int j = -radius; j <= radius; ++j) {
      const int c = px + j;
      if (c <= 0 || c >= img.cols - 1) continue;
      // Sample position in cell units of the rotated window, cell centres at integers.
      const float c_rot = j * cos_t - i * sin_t;
      const float r_rot = j * sin_t + i * cos_t;
      const float rbin = r_rot + d / 2 - 0.5f;
      const float cbin = c_rot + d / 2 - 0.5f;
      if (!(rbin > -1 && rbin < d && cbin > -1 && cbin < d)) continue;
      w.gradient.dx[m] = row[c + 1] - row[c - 1];
      w.gradient.dy[m] = up[c] - down[c];
      w.gradient.weight[m] = gi * g[std::abs(j)];
      w.rbin[m] = rbin;
      w.cbin[m] = cbin;
      ++m;
    }
  }
  w.gradient.ToPolar(m);

  // (d+2) x (d+2) x (n+2): one cell of margin on each side and two wrap bins, so the
  // trilinear spread never needs a bounds test.
  float hist[(d + 2) * (d + 2) * (n + 2)] = {};
  for (int k = 0; k < m; ++k) {
    const float rbin = w.rbin[k], cbin = w.cbin[k], mag = w.gradient.mag[k];
    const float obin = (w.gradient.deg[k] - angle) * bins_per_degree;
    const int r0 = FloorInt(rbin);
    const int c0 = FloorInt(cbin);
    int o0 = FloorInt(obin);
    const float fr = rbin - r0, fc = cbin - c0, fo = obin - o0;
    if (o0 < 0) o0 += n;
    if (o0 >= n) o0 -= n;
    // Trilinear split of the weighted magnitude over the 8 neighbouring bins.
    const float v_r1 = mag * fr, v_r0 = mag - v_r1;
    const float v_rc11 = v_r1 * fc, v_rc10 = v_r1 - v_rc11;
    const float v_rc01 = v_r0 * fc, v_rc00 = v_r0 - v_rc01;
    const float v_rco111 = v_rc11 * fo, v_rco110 = v_rc11 - v_rco111;
    const float v_rco101 = v_rc10 * fo, v_rco100 = v_rc10 - v_rco101;
    const float v_rco011 = v_rc01 * fo, v_rco010 = v_rc01 - v_rco011;
    const float v_rco001 = v_rc00 * fo, v_rco000 = v_rc00 - v_rco001;
    const int idx = ((r0 + 1) * (d + 2) + c0 + 1) * (n + 2) + o0;
    hist[idx] += v_rco000;
    hist[idx + 1] += v_rco001;
    hist[idx + (n + 2)] += v_rco010;
    hist[idx + (n + 3)] += v_rco011;
    hist[idx + (d + 2) * (n + 2)] += v_rco100;
    hist[idx + (d + 2) * (n + 2) + 1] += v_rco101;
    hist[idx + (d + 3) * (n + 2)] += v_rco110;
    hist[idx + (d + 3) * (n + 2) + 1] += v_rco111;
  }
  // Fold the wrap bins (orientation is circular) and drop the spatial margin.
  for (int i = 0; i < d; ++i)
    for (int j = 0; j < d; ++j) {
      const int idx = ((i + 1) * (d + 2) + (j + 1)) * (n + 2);
      hist[idx] += hist[idx + n];
      hist[idx + 1] += hist[idx + n + 1];
      for (int k = 0; k < n; ++k) out[(i * d + j) * n + k] = hist[idx + k];
    }
  // Normalise, clip (robustness to non-linear illumination), normalise again.
  const int len = d * d * n;
  float norm2 = 0;
  for (int k = 0; k < len; ++k) norm2 += out[k] * out[k];
  const float clip = std::sqrt(norm2) * kClip;
  norm2 = 0;
  for (int k = 0; k < len; ++k) {
    out[k] = std::min(out[k], clip);
    norm2 += out[k] * out[k];
  }
  const float scale = kOutputNorm / std::max(std::sqrt(norm2), FLT_EPSILON);
  for (int k = 0; k < len; ++k) out[k] *= scale;
}

}  // namespace pgba
