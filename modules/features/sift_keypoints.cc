#include "features/sift_keypoints.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <numeric>
#include <set>
#include <tuple>
#include <vector>

#include "features/gradient_polar.h"
#include "features/sift_extrema_scan.h"
#include "features/separable_gaussian.h"
#include "pgba/io/option_ranges.h"

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

// Rows [row0, row1) of an octave, searched in every layer 1..s row by row: the 3 x 6 rows
// around row r of the octave's Gaussian layers stay in cache from one layer's scan to the
// next (a layer at a time read each Gaussian layer from memory up to 4 times).
struct Block {
  int octave, row0, row1;
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
  // The window's samples in row-major order, their angles and magnitudes 8 at a time
  // (gradient_polar.h: the same bits as one at a time), then the histogram in that order.
  thread_local GradientSamples w;
  w.Reserve((2 * radius + 1) * (2 * radius + 1));
  int m = 0;
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
      w.dx[m] = row[x + 1] - row[x - 1];
      w.dy[m] = up[x] - down[x];
      w.weight[m] = gi * g[std::abs(j)];
      ++m;
    }
  }
  w.ToPolar(m);
  for (int k = 0; k < m; ++k) {
    // deg >= 0: round half up without lround's libm call (a tenth of the histogram time).
    int bin = static_cast<int>(w.deg[k] * (kOrientationBins / 360.f) + 0.5f);
    if (bin >= kOrientationBins) bin -= kOrientationBins;
    if (bin < 0) bin += kOrientationBins;
    h[bin] += w.mag[k];
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

// Extrema of one block of rows of octave b.octave, out[l - 1] those of DoG layer l (1..s).
void SearchBlock(const SiftScaleSpace& ss, const Block& b, const SiftDetectionOptions& opt,
                 std::vector<std::vector<SiftExtremum>>* out) {
  const std::vector<cv::Mat>& g = ss.gaussians[b.octave];
  const int s = ss.layers_per_octave;
  const int cols = g[0].cols;
  const ptrdiff_t step = static_cast<ptrdiff_t>(g[0].step1());
  for (const cv::Mat& layer : g) CV_Assert(layer.step1() == g[0].step1());
  // Pre-filter: samples below half the contrast threshold are not refined (OpenCV's and
  // VLFeat's rule; refinement only moves towards larger |DoG|, so a candidate must at least
  // double to pass). OpenCV rounds it down to whole grey levels, 0 at pgba's 0.02, and so
  // refines every non-zero extremum: most of its extrema time, for no kept keypoint.
  const float pre = 0.5f * static_cast<float>(opt.contrast_threshold) / s * 255.f;
  std::vector<int> found(std::max(cols - 2 * kBorder, 0));
  out->assign(s, {});
  for (int r = b.row0; r < b.row1; ++r) {
    for (int l = 1; l <= s; ++l) {
      // DoG layers l - 1, l, l + 1 are differences of Gaussian layers l - 1 .. l + 2.
      const int n = ScanDogRowForExtrema(g[l - 1].ptr<float>(r), g[l].ptr<float>(r), g[l + 1].ptr<float>(r),
                                         g[l + 2].ptr<float>(r), step, kBorder, cols - kBorder, pre, found.data());
      for (int i = 0; i < n; ++i) {
        SiftKeypoint kp;
        int rr = r, rc = found[i];
        if (!Refine(ss, b.octave, l, rr, rc, opt, &kp)) continue;
        (*out)[l - 1].push_back({kp, rr, rc});
      }
    }
  }
}

}  // namespace

void FindSiftExtrema(const SiftScaleSpace& ss, int octave, const SiftDetectionOptions& options,
                     std::vector<SiftExtremum>* extrema) {
  std::vector<Block> blocks;
  const int rows = ss.gaussians[octave][0].rows, cols = ss.gaussians[octave][0].cols;
  if (rows <= 2 * kBorder || cols <= 2 * kBorder) return;
  for (int r = kBorder; r < rows - kBorder; r += kBlockRows)
    blocks.push_back({octave, r, std::min(r + kBlockRows, rows - kBorder)});
  std::vector<std::vector<std::vector<SiftExtremum>>> found(blocks.size());
  tbb::parallel_for(size_t(0), blocks.size(), [&](size_t i) { SearchBlock(ss, blocks[i], options, &found[i]); });
  // In the order (layer, row, column), whatever the blocks' order of completion.
  const size_t first = extrema->size();
  for (int l = 0; l < ss.layers_per_octave; ++l)
    for (const auto& block : found) extrema->insert(extrema->end(), block[l].begin(), block[l].end());
  // Refinements that end on the same sample give the same keypoint (its values depend on that
  // sample only). OpenCV removes such duplicates (KeyPointsFilter::removeDuplicatedSorted:
  // equal position, size and angle) before its cap; kept, each is two identical descriptors in
  // one image, and Lowe's ratio test then rejects every match of either (0.1-1% of the
  // keypoints of the Middlebury rings and of a Strecha photo). The first one is kept.
  std::set<std::tuple<int, int, int>> seen;
  const auto end = std::remove_if(extrema->begin() + first, extrema->end(), [&](const SiftExtremum& e) {
    return !seen.emplace(e.kp.layer, e.row, e.col).second;
  });
  extrema->erase(end, extrema->end());
}

std::vector<SiftKeypoint> OrientSiftExtrema(const SiftScaleSpace& ss, const std::vector<SiftExtremum>& extrema,
                                            const SiftDetectionOptions& options) {
  // Orientations (one keypoint per dominant one, possibly none) at the integer sample and
  // layer where each refinement ended; oriented[i] holds extremum i's.
  const size_t n = extrema.size();
  std::vector<std::vector<SiftKeypoint>> oriented(n);
  auto orient = [&](size_t i) { AddOriented(ss, extrema[i].kp, extrema[i].row, extrema[i].col, &oriented[i]); };
  if (options.max_features <= 0) {
    tbb::parallel_for(size_t(0), n, orient);
  } else {
    // Strongest first (ties in extremum order); a 6 MP photo has ~20,000 extrema for the
    // 8,192 kept, and the orientation histograms were most of the detection time. Batches
    // until max_features oriented keypoints are reached at response r_k, then every extremum
    // tied with r_k: the rest are weaker than max_features oriented keypoints already.
    std::vector<size_t> by_response(n);
    std::iota(by_response.begin(), by_response.end(), size_t(0));
    std::stable_sort(by_response.begin(), by_response.end(),
                     [&](size_t a, size_t b) { return extrema[a].kp.response > extrema[b].kp.response; });
    const size_t cap = static_cast<size_t>(options.max_features);
    size_t done = 0, count = 0;
    bool reached = false;
    float r_k = 0;
    while (done < n) {
      size_t end = done;
      if (!reached)
        end = std::min(n, done + std::max<size_t>(cap - count, 64));
      else
        while (end < n && extrema[by_response[end]].kp.response >= r_k) ++end;
      if (end == done) break;
      // In extremum order (the scale space's), where neighbouring windows share cache lines.
      std::vector<size_t> batch(by_response.begin() + done, by_response.begin() + end);
      std::sort(batch.begin(), batch.end());
      tbb::parallel_for(size_t(0), batch.size(), [&](size_t i) { orient(batch[i]); });
      for (size_t i = done; i < end; ++i) {
        count += oriented[by_response[i]].size();
        if (!reached && count >= cap) {
          reached = true;
          r_k = extrema[by_response[i]].kp.response;
        }
      }
      done = end;
    }
  }
  std::vector<SiftKeypoint> all;
  for (const auto& o : oriented) all.insert(all.end(), o.begin(), o.end());
  return all;
}

std::string SiftDetectionOptions::Check() const { return CheckRanges(*this, "SiftDetectionOptions"); }

}  // namespace pgba
