#include "features/sift_keypoints.h"

#include <emmintrin.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "features/fast_atan2.h"
#include "features/separable_gaussian.h"

namespace pgba {
namespace {

constexpr int kBorder = 5;             // no extrema this close to an octave's edge
constexpr int kMaxRefineSteps = 5;     // Newton steps before an extremum is given up
constexpr int kOrientationBins = 36;
constexpr float kOrientationRadius = 4.5f;  // window radius, in units of the keypoint sigma
constexpr float kOrientationSigma = 1.5f;   // Gaussian weight of the window, same units
constexpr float kPeakRatio = 0.8f;          // secondary orientations above this x the maximum
constexpr int kBlockRows = 32;              // rows per search task (fixed: the output order)
constexpr float kGreyScale = 1.f / 255.f;   // DoG values are in grey levels 0..255

// A DoG layer, computed where it is read (gaussians[l + 1] - gaussians[l]: the same float
// subtraction as a stored one, so the same values) instead of stored: the upsampled octave's
// five DoG images were 500 MB of fresh memory per 6 MP image.
struct DogLayer {
  const cv::Mat* hi;
  const cv::Mat* lo;
  float operator()(int y, int x) const { return hi->ptr<float>(y)[x] - lo->ptr<float>(y)[x]; }
};

struct Block {
  int octave, layer, row0, row1;
};

// Newton refinement of an extremum at (layer, r, c) of octave o; on success fills kp and
// leaves r, c at the integer sample the refinement ended on.
bool Refine(const SiftScaleSpace& ss, int o, int layer, int& r, int& c, const SiftDetectionOptions& opt,
            SiftKeypoint* kp) {
  const int s = ss.layers_per_octave;
  const std::vector<cv::Mat>& g = ss.gaussians[o];
  const int rows = g[0].rows, cols = g[0].cols;
  auto dog = [&g](int l) { return DogLayer{&g[l + 1], &g[l]}; };
  const float ds = 0.5f * kGreyScale, dss = kGreyScale, dcs = 0.25f * kGreyScale;
  float xi = 0, xr = 0, xc = 0;
  int step = 0;
  for (; step < kMaxRefineSteps; ++step) {
    const DogLayer img = dog(layer), prev = dog(layer - 1), next = dog(layer + 1);
    auto at = [](const DogLayer& m, int y, int x) { return m(y, x); };
    const float v2 = 2 * at(img, r, c);
    const float gx = (at(img, r, c + 1) - at(img, r, c - 1)) * ds;
    const float gy = (at(img, r + 1, c) - at(img, r - 1, c)) * ds;
    const float gs = (at(next, r, c) - at(prev, r, c)) * ds;
    const float hxx = (at(img, r, c + 1) + at(img, r, c - 1) - v2) * dss;
    const float hyy = (at(img, r + 1, c) + at(img, r - 1, c) - v2) * dss;
    const float hss = (at(next, r, c) + at(prev, r, c) - v2) * dss;
    const float hxy =
        (at(img, r + 1, c + 1) - at(img, r + 1, c - 1) - at(img, r - 1, c + 1) + at(img, r - 1, c - 1)) * dcs;
    const float hxs =
        (at(next, r, c + 1) - at(next, r, c - 1) - at(prev, r, c + 1) + at(prev, r, c - 1)) * dcs;
    const float hys =
        (at(next, r + 1, c) - at(next, r - 1, c) - at(prev, r + 1, c) + at(prev, r - 1, c)) * dcs;
    const cv::Matx33f H(hxx, hxy, hxs, hxy, hyy, hys, hxs, hys, hss);
    const cv::Vec3f X = H.solve(cv::Vec3f(gx, gy, gs), cv::DECOMP_LU);
    xc = -X[0];
    xr = -X[1];
    xi = -X[2];
    if (std::abs(xi) < 0.5f && std::abs(xr) < 0.5f && std::abs(xc) < 0.5f) break;
    if (std::abs(xi) > 1e6f || std::abs(xr) > 1e6f || std::abs(xc) > 1e6f) return false;
    c += static_cast<int>(std::lround(xc));
    r += static_cast<int>(std::lround(xr));
    layer += static_cast<int>(std::lround(xi));
    if (layer < 1 || layer > s || c < kBorder || c >= cols - kBorder || r < kBorder || r >= rows - kBorder)
      return false;
  }
  if (step >= kMaxRefineSteps) return false;

  const DogLayer img = dog(layer), prev = dog(layer - 1), next = dog(layer + 1);
  auto at = [](const DogLayer& m, int y, int x) { return m(y, x); };
  const float gx = (at(img, r, c + 1) - at(img, r, c - 1)) * ds;
  const float gy = (at(img, r + 1, c) - at(img, r - 1, c)) * ds;
  const float gs = (at(next, r, c) - at(prev, r, c)) * ds;
  const float contrast = at(img, r, c) * kGreyScale + 0.5f * (gx * xc + gy * xr + gs * xi);
  if (std::abs(contrast) * s < opt.contrast_threshold) return false;
  // Edge response: an edge has one large and one small principal curvature.
  const float v2 = 2 * at(img, r, c);
  const float hxx = (at(img, r, c + 1) + at(img, r, c - 1) - v2) * dss;
  const float hyy = (at(img, r + 1, c) + at(img, r - 1, c) - v2) * dss;
  const float hxy = (at(img, r + 1, c + 1) - at(img, r + 1, c - 1) - at(img, r - 1, c + 1) + at(img, r - 1, c - 1)) * dcs;
  const float tr = hxx + hyy, det = hxx * hyy - hxy * hxy;
  const float e = static_cast<float>(opt.edge_threshold);
  if (det <= 0 || tr * tr * e >= (e + 1) * (e + 1) * det) return false;

  kp->octave = o;
  kp->layer = layer;
  kp->x = c + xc;
  kp->y = r + xr;
  kp->sigma = static_cast<float>(ss.sigma * std::pow(2.0f, (layer + xi) / s));
  kp->response = std::abs(contrast);
  return true;
}

// Smoothed 36-bin histogram of gradient directions around (x, y) of a Gaussian layer,
// weighted by magnitude and a Gaussian window; returns its maximum.
float OrientationHistogram(const cv::Mat& img, int x0, int y0, int radius, float sigma, float* hist) {
  float raw[kOrientationBins + 4] = {};
  float* h = raw + 2;
  const float exp_scale = -1.f / (2.f * sigma * sigma);
  // The Gaussian window is separable: exp(-(i^2 + j^2) / 2s^2) = g[i] g[j], one exp per
  // offset instead of one per sample (the exps were a third of the orientation time).
  const SeparableGaussian g(radius, exp_scale);
  for (int i = -radius; i <= radius; ++i) {
    const int y = y0 + i;
    if (y <= 0 || y >= img.rows - 1) continue;
    const float* row = img.ptr<float>(y);
    const float* up = img.ptr<float>(y - 1);
    const float* down = img.ptr<float>(y + 1);
    const float gi = g[std::abs(i)];
    for (int j = -radius; j <= radius; ++j) {
      const int x = x0 + j;
      if (x <= 0 || x >= img.cols - 1) continue;
      const float dx = row[x + 1] - row[x - 1];
      const float dy = up[x] - down[x];
      const float w = gi * g[std::abs(j)];
      const float deg = FastAtan2Degrees(dy, dx);
      // deg >= 0: round half up without lround's libm call (a tenth of the histogram time).
      int bin = static_cast<int>(deg * (kOrientationBins / 360.f) + 0.5f);
      if (bin >= kOrientationBins) bin -= kOrientationBins;
      if (bin < 0) bin += kOrientationBins;
      h[bin] += w * std::sqrt(dx * dx + dy * dy);
    }
  }
  // Circular [1 4 6 4 1] / 16 smoothing.
  h[-1] = h[kOrientationBins - 1];
  h[-2] = h[kOrientationBins - 2];
  h[kOrientationBins] = h[0];
  h[kOrientationBins + 1] = h[1];
  float best = 0;
  for (int b = 0; b < kOrientationBins; ++b) {
    hist[b] = (h[b - 2] + h[b + 2]) * (1.f / 16) + (h[b - 1] + h[b + 1]) * (4.f / 16) + h[b] * (6.f / 16);
    best = std::max(best, hist[b]);
  }
  return best;
}

// The keypoint once per dominant orientation (parabolic peak interpolation).
void AddOriented(const SiftScaleSpace& ss, const SiftKeypoint& kp, int r, int c, std::vector<SiftKeypoint>* out) {
  float hist[kOrientationBins];
  const cv::Mat& img = ss.gaussians[kp.octave][kp.layer];
  const float best = OrientationHistogram(img, c, r, static_cast<int>(std::lround(kOrientationRadius * kp.sigma)),
                                          kOrientationSigma * kp.sigma, hist);
  const float threshold = best * kPeakRatio;
  for (int j = 0; j < kOrientationBins; ++j) {
    const int l = j > 0 ? j - 1 : kOrientationBins - 1;
    const int rt = j < kOrientationBins - 1 ? j + 1 : 0;
    if (hist[j] > hist[l] && hist[j] > hist[rt] && hist[j] >= threshold) {
      float bin = j + 0.5f * (hist[l] - hist[rt]) / (hist[l] - 2 * hist[j] + hist[rt]);
      bin = bin < 0 ? kOrientationBins + bin : bin >= kOrientationBins ? bin - kOrientationBins : bin;
      SiftKeypoint o = kp;
      o.angle = 360.f - (360.f / kOrientationBins) * bin;
      if (std::abs(o.angle - 360.f) < FLT_EPSILON) o.angle = 0.f;
      out->push_back(o);
    }
  }
}

// Bit i set when column i of p[0..7] may be an extremum: |v| > pre and v >= its 8
// neighbours in the same layer (v > 0), or v <= them (v < 0). SSE2, 4 columns at a time.
inline uint32_t CandidateMask(const float* p_hi, const float* p_lo, ptrdiff_t step, float pre) {
  const ptrdiff_t around[8] = {-step - 1, -step, -step + 1, -1, 1, step - 1, step, step + 1};
  const __m128 hi_t = _mm_set1_ps(pre), lo_t = _mm_set1_ps(-pre);
  uint32_t bits = 0;
  for (int half = 0; half < 2; ++half) {
    const float* qh = p_hi + 4 * half;
    const float* ql = p_lo + 4 * half;
    const __m128 v = _mm_sub_ps(_mm_loadu_ps(qh), _mm_loadu_ps(ql));
    __m128 hi = _mm_cmpgt_ps(v, hi_t), lo = _mm_cmplt_ps(v, lo_t);
    if (_mm_movemask_ps(_mm_or_ps(hi, lo)) == 0) continue;
    for (int k = 0; k < 8; ++k) {
      const __m128 n = _mm_sub_ps(_mm_loadu_ps(qh + around[k]), _mm_loadu_ps(ql + around[k]));
      hi = _mm_and_ps(hi, _mm_cmpge_ps(v, n));
      lo = _mm_and_ps(lo, _mm_cmple_ps(v, n));
    }
    bits |= static_cast<uint32_t>(_mm_movemask_ps(_mm_or_ps(hi, lo))) << (4 * half);
  }
  return bits;
}

// Extrema of one block of rows of DoG layer `layer` (1..s) of octave o.
void SearchBlock(const SiftScaleSpace& ss, const Block& b, const SiftDetectionOptions& opt,
                 std::vector<SiftKeypoint>* out) {
  const std::vector<cv::Mat>& g = ss.gaussians[b.octave];
  // DoG layers l - 1, l, l + 1 are differences of Gaussian layers l - 1 .. l + 2.
  const cv::Mat &g0 = g[b.layer - 1], &g1 = g[b.layer], &g2 = g[b.layer + 1], &g3 = g[b.layer + 2];
  const int cols = g1.cols;
  const ptrdiff_t step = static_cast<ptrdiff_t>(g1.step1());
  CV_Assert(g0.step1() == g1.step1() && g2.step1() == g1.step1() && g3.step1() == g1.step1());
  // The 26 neighbours: 8 in the same layer first (most candidates fail there), then 9 + 9.
  const ptrdiff_t around[9] = {-step - 1, -step, -step + 1, -1, 0, 1, step - 1, step, step + 1};
  // Pre-filter: samples below half the contrast threshold are not refined (OpenCV's and
  // VLFeat's rule; refinement only moves towards larger |DoG|, so a candidate must at least
  // double to pass). OpenCV rounds it down to whole grey levels, 0 at pgba's 0.02, and so
  // refines every non-zero extremum: most of its extrema time, for no kept keypoint.
  const float pre = 0.5f * static_cast<float>(opt.contrast_threshold) / ss.layers_per_octave * 255.f;
  for (int r = b.row0; r < b.row1; ++r) {
    const float* q0 = g0.ptr<float>(r);
    const float* q1 = g1.ptr<float>(r);
    const float* q2 = g2.ptr<float>(r);
    const float* q3 = g3.ptr<float>(r);
    auto pc = [q1, q2](ptrdiff_t i) { return q2[i] - q1[i]; };
    auto pp = [q0, q1](ptrdiff_t i) { return q1[i] - q0[i]; };
    auto pn = [q2, q3](ptrdiff_t i) { return q3[i] - q2[i]; };
    // 8 columns at a time, the pre-filter and the 8 neighbours of the same layer as a mask
    // (the same tests as the scalar code below, which decides): most of the image fails
    // there, and the scan was the largest part of the extrema time.
    uint32_t candidates = 0;
    int c0 = kBorder;
    for (int c = kBorder; c < cols - kBorder; ++c) {
      if (c == c0) {
        candidates = c + 8 <= cols - kBorder ? CandidateMask(q2 + c, q1 + c, step, pre) : 0xffu;
        c0 = c + 8;
        if (candidates == 0) {
          c += 7;
          continue;
        }
      }
      if (!(candidates >> (c - (c0 - 8)) & 1u)) continue;
      const float v = pc(c);
      if (!(std::abs(v) > pre)) continue;
      bool extremum = true;
      if (v > 0) {
        for (int k = 0; k < 9 && extremum; ++k) extremum = (k == 4 || v >= pc(c + around[k]));
        for (int k = 0; k < 9 && extremum; ++k) extremum = v >= pp(c + around[k]) && v >= pn(c + around[k]);
      } else {
        for (int k = 0; k < 9 && extremum; ++k) extremum = (k == 4 || v <= pc(c + around[k]));
        for (int k = 0; k < 9 && extremum; ++k) extremum = v <= pp(c + around[k]) && v <= pn(c + around[k]);
      }
      if (!extremum) continue;
      SiftKeypoint kp;
      int rr = r, rc = c;
      if (!Refine(ss, b.octave, b.layer, rr, rc, opt, &kp)) continue;
      // Orientation at the integer sample and layer where the refinement ended.
      AddOriented(ss, kp, rr, rc, out);
    }
  }
}

}  // namespace

std::vector<SiftKeypoint> DetectSiftKeypoints(const SiftScaleSpace& ss, const SiftDetectionOptions& options) {
  std::vector<Block> blocks;
  for (int o = 0; o < ss.num_octaves(); ++o) {
    const int rows = ss.gaussians[o][0].rows, cols = ss.gaussians[o][0].cols;
    if (rows <= 2 * kBorder || cols <= 2 * kBorder) continue;
    for (int layer = 1; layer <= ss.layers_per_octave; ++layer)
      for (int r = kBorder; r < rows - kBorder; r += kBlockRows)
        blocks.push_back({o, layer, r, std::min(r + kBlockRows, rows - kBorder)});
  }
  std::vector<std::vector<SiftKeypoint>> found(blocks.size());
  tbb::parallel_for(size_t(0), blocks.size(), [&](size_t i) { SearchBlock(ss, blocks[i], options, &found[i]); });
  std::vector<SiftKeypoint> all;
  for (const auto& f : found) all.insert(all.end(), f.begin(), f.end());
  return all;
}

}  // namespace pgba
