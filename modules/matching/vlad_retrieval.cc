#include "matching/vlad_retrieval.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>
#include <set>

#include "pgba/io/option_ranges.h"
#include "features/feature_set.h"

namespace pgba {
namespace {

// uint8 descriptors on the 512 scale -> float rows of (about) unit norm.
Eigen::MatrixXf ToFloat(const cv::Mat& u8) {
  Eigen::MatrixXf out(u8.rows, kSiftDescriptorSize);
  for (int r = 0; r < u8.rows; ++r)
    for (int c = 0; c < kSiftDescriptorSize; ++c) out(r, c) = u8.at<uint8_t>(r, c) / 512.f;
  return out;
}

}  // namespace

cv::Mat TrainVladVocabulary(const std::vector<cv::Mat>& descriptors, const VladOptions& options) {
  size_t total = 0;
  for (const cv::Mat& d : descriptors) total += d.rows;
  const size_t budget = std::max<size_t>(1, options.max_training_descriptors);
  const size_t stride = std::max<size_t>(1, (total + budget - 1) / budget);
  // Every stride-th descriptor of every image: deterministic and spread over all images.
  cv::Mat sample;
  for (const cv::Mat& d : descriptors)
    for (int r = 0; r < d.rows; r += static_cast<int>(stride)) {
      cv::Mat row;
      d.row(r).convertTo(row, CV_32F, 1.0 / 512.0);
      sample.push_back(row);
    }
  const int k = std::min(options.num_words, sample.rows);
  if (k < 1) return cv::Mat(0, kSiftDescriptorSize, CV_32F);
  cv::theRNG() = cv::RNG(options.seed + 1);  // k-means++ seeding draws from the thread's RNG
  cv::Mat labels, words;
  cv::kmeans(sample, k, labels,
             cv::TermCriteria(cv::TermCriteria::MAX_ITER + cv::TermCriteria::EPS, options.kmeans_iterations, 1e-4), 1,
             cv::KMEANS_PP_CENTERS, words);
  return words;
}

Eigen::VectorXf ComputeVlad(const cv::Mat& descriptors_u8, const cv::Mat& words) {
  const int k = words.rows;
  Eigen::MatrixXf vlad = Eigen::MatrixXf::Zero(kSiftDescriptorSize, k);
  if (descriptors_u8.rows == 0 || k == 0) return Eigen::Map<Eigen::VectorXf>(vlad.data(), vlad.size());
  const Eigen::MatrixXf d = ToFloat(descriptors_u8);
  Eigen::MatrixXf w(k, kSiftDescriptorSize);
  for (int r = 0; r < k; ++r)
    for (int c = 0; c < kSiftDescriptorSize; ++c) w(r, c) = words.at<float>(r, c);
  // Nearest word: argmin ||w||^2 - 2 d.w (||d||^2 is common to all words).
  const Eigen::MatrixXf score = (-2.f * d * w.transpose()).rowwise() + w.rowwise().squaredNorm().transpose();
  for (int i = 0; i < d.rows(); ++i) {
    Eigen::Index best;
    score.row(i).minCoeff(&best);
    vlad.col(best) += (d.row(i) - w.row(best)).transpose();
  }
  // Intra-normalisation, then signed square root, then global L2.
  for (int c = 0; c < k; ++c) {
    const float n = vlad.col(c).norm();
    if (n > 0) vlad.col(c) /= n;
  }
  Eigen::VectorXf v = Eigen::Map<Eigen::VectorXf>(vlad.data(), vlad.size());
  v = v.unaryExpr([](float x) { return x < 0 ? -std::sqrt(-x) : std::sqrt(x); });
  const float n = v.norm();
  if (n > 0) v /= n;
  return v;
}

std::vector<std::pair<uint32_t, uint32_t>> RetrievalPairs(const std::vector<cv::Mat>& descriptors,
                                                          const VladOptions& options) {
  const int n = static_cast<int>(descriptors.size());
  const cv::Mat words = TrainVladVocabulary(descriptors, options);
  Eigen::MatrixXf vlads(128 * std::max(words.rows, 0), n);
  tbb::parallel_for(0, n, [&](int i) { vlads.col(i) = ComputeVlad(descriptors[i], words); });
  const Eigen::MatrixXf similarity = vlads.transpose() * vlads;

  std::set<std::pair<uint32_t, uint32_t>> pairs;
  const int k = std::min(options.neighbors, n - 1);
  std::vector<int> order;
  for (int i = 0; i < n; ++i) {
    // Every image but i, afresh for each i (erasing from one shared list shrank it by one
    // per image, so that from the middle of the list on the erase ran past its end).
    order.resize(n);
    std::iota(order.begin(), order.end(), 0);
    order.erase(order.begin() + i);
    // Most similar first; ties by index for determinism.
    std::partial_sort(order.begin(), order.begin() + k, order.end(), [&](int a, int b) {
      if (similarity(i, a) != similarity(i, b)) return similarity(i, a) > similarity(i, b);
      return a < b;
    });
    for (int r = 0; r < k; ++r)
      pairs.emplace(static_cast<uint32_t>(std::min(i, order[r])), static_cast<uint32_t>(std::max(i, order[r])));
  }
  return {pairs.begin(), pairs.end()};
}

std::string VladOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "matching.pairs.vlad"); !m.empty()) return m;
  return "";
}

}  // namespace pgba
