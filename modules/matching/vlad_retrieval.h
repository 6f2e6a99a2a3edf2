// Image retrieval for pair selection on large sets: VLAD (Jegou et al., CVPR 2010,
// "Aggregating local descriptors into a compact image representation") over the images'
// own SIFT descriptors.
//   1. Vocabulary: k-means (k = num_words) on a deterministic sample of descriptors from
//      all images.
//   2. Per image: sum of residuals (descriptor - nearest word) per word, each word's block
//      L2-normalised ("intra-normalisation", Arandjelovic & Zisserman CVPR 2013), signed
//      square root, global L2 normalisation.
//   3. Similarity = dot product; each image keeps its `neighbors` most similar images.
#pragma once

#include <string>

#include <Eigen/Core>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <utility>
#include <vector>

namespace pgba {

struct VladOptions {
  int neighbors = 20;  // pairs per image (before symmetrisation)
  int num_words = 64;  // k-means vocabulary size; VLAD dimension = 128 * num_words
  int max_training_descriptors = 100000;
  int kmeans_iterations = 20;
  uint64_t seed = 0;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(VladOptions, neighbors, num_words, max_training_descriptors,
                                                kmeans_iterations, seed)

// k-means words (num_words x 128, CV_32F) from a sample of every image's descriptors.
cv::Mat TrainVladVocabulary(const std::vector<cv::Mat>& descriptors, const VladOptions& options);

// The normalised VLAD vector of one image (empty descriptors -> zero vector).
Eigen::VectorXf ComputeVlad(const cv::Mat& descriptors_u8, const cv::Mat& words);

// Pairs (i < j) of images among each other's top `neighbors` by VLAD similarity, sorted:
// at most n * neighbors pairs, and every image is in at least min(neighbors, n - 1).
std::vector<std::pair<uint32_t, uint32_t>> RetrievalPairs(const std::vector<cv::Mat>& descriptors,
                                                          const VladOptions& options);

}  // namespace pgba
