// SIFT extraction: the downscaling path maps keypoints exactly back to full resolution,
// RootSIFT descriptors have the Hellinger normalisation, the feature cap and the order
// hold, and the cache file round-trips and rejects damage.
#include "features/sift_extractor.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <opencv2/imgproc.hpp>

#include "features/feature_file.h"
#include "pgba/util/error.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

// A textured test image: smoothed noise plus a few discs and rectangles.
cv::Mat TexturedImage(int w, int h, uint64_t seed) {
  cv::Mat img(h, w, CV_8U);
  cv::RNG rng(seed);
  rng.fill(img, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(img, img, cv::Size(0, 0), 2.0);
  for (int k = 0; k < 40; ++k) {
    cv::circle(img, {rng.uniform(0, w), rng.uniform(0, h)}, rng.uniform(3, 20), cv::Scalar(rng.uniform(0, 256)), -1);
    cv::rectangle(img, cv::Rect(rng.uniform(0, w), rng.uniform(0, h), rng.uniform(4, 30), rng.uniform(4, 30)),
                  cv::Scalar(rng.uniform(0, 256)), -1);
  }
  return img;
}

TEST(SiftExtractor, DownscaledKeypointsAreInFullResolutionPixels) {
  // An image and its exact 2x nearest-neighbour enlargement: INTER_AREA downscaling of the
  // enlargement gives back the original bit for bit, so the keypoints found on the
  // enlargement with max_image_size = original size must be the original's, scaled by 2
  // about the pixel-corner origin (COLMAP convention: x_full = 2 x).
  const cv::Mat small = TexturedImage(320, 240, 1);
  cv::Mat big;
  cv::resize(small, big, cv::Size(640, 480), 0, 0, cv::INTER_NEAREST);
  SiftOptions opt;
  opt.max_image_size = 0;
  const FeatureSet fs_small = ExtractSift(small, opt);
  opt.max_image_size = 320;
  const FeatureSet fs_big = ExtractSift(big, opt);
  ASSERT_GT(fs_small.size(), 100u);
  ASSERT_EQ(fs_small.size(), fs_big.size());
  EXPECT_EQ(fs_big.width, 640);
  EXPECT_EQ(fs_big.height, 480);
  EXPECT_DOUBLE_EQ(DetectionScale(640, 480, opt), 2.0);
  for (size_t i = 0; i < fs_small.size(); ++i) {
    EXPECT_NEAR(fs_big.keypoints[i].x, 2 * fs_small.keypoints[i].x, 1e-3);
    EXPECT_NEAR(fs_big.keypoints[i].y, 2 * fs_small.keypoints[i].y, 1e-3);
    EXPECT_NEAR(fs_big.keypoints[i].scale, 2 * fs_small.keypoints[i].scale, 1e-3);
  }
  EXPECT_EQ(cv::norm(fs_small.descriptors, fs_big.descriptors, cv::NORM_L1), 0.0);
}

TEST(SiftExtractor, PixelCentreConventionIsColmaps) {
  // A bright blob centred on pixel (40, 30) in OpenCV's integer-centre convention is at
  // (40.5, 30.5) in COLMAP's: the detector's strongest keypoint must sit there, whichever
  // octave the scale space starts at.
  cv::Mat img(64, 80, CV_8U, cv::Scalar(0));
  cv::circle(img, {40, 30}, 4, cv::Scalar(255), -1);
  cv::GaussianBlur(img, img, cv::Size(0, 0), 1.5);
  for (const char* implementation : {"opencv", "pgba"})
    for (int first_octave : {-1, 0}) {
      SiftOptions opt;
      opt.implementation = implementation;
      opt.max_image_size = 0;
      opt.first_octave = first_octave;
      const FeatureSet f = ExtractSift(img, opt);
      ASSERT_GE(f.size(), 1u);
      EXPECT_NEAR(f.keypoints[0].x, 40.5, 0.05) << implementation << " " << first_octave;
      EXPECT_NEAR(f.keypoints[0].y, 30.5, 0.05) << implementation << " " << first_octave;
    }
  SiftOptions bad;
  bad.first_octave = 1;
  EXPECT_THROW(ExtractSift(img, bad), InputError);
}

TEST(SiftExtractor, AnalyticGaussianBlobAtItsPositionAndScale) {
  // A Gaussian blob exp(-r^2 / 2 s0^2) is the scale-normalised Laplacian's extremum at its
  // centre and at the blur sigma where sigma^2 / (s0^2 + sigma^2 - 0.5^2)^2 peaks (the scale
  // space assumes 0.5 px of camera blur already in the image): sigma = sqrt(s0^2 - 0.25).
  // SIFT's DoG between layers sigma and k sigma (k = 2^(1/3)) is (k - 1) times the
  // normalised Laplacian at their geometric mean sqrt(k) sigma, and the keypoint is given the
  // lower layer's sigma: expected scale sqrt(s0^2 - 0.25) / 2^(1/6). Each implementation's
  // strongest keypoint must be there: position to 0.05 px, scale to 3%.
  const double s0 = 6.0, cx = 100.3, cy = 80.7;  // centre in OpenCV's integer-centre pixels
  cv::Mat blob(160, 200, CV_32F);
  for (int y = 0; y < blob.rows; ++y)
    for (int x = 0; x < blob.cols; ++x)
      blob.at<float>(y, x) = static_cast<float>(
          30 + 200 * std::exp(-((x - cx) * (x - cx) + (y - cy) * (y - cy)) / (2 * s0 * s0)));
  cv::Mat img;
  blob.convertTo(img, CV_8U);
  const double expected_scale = std::sqrt(s0 * s0 - 0.25) / std::pow(2.0, 1.0 / 6);
  for (const char* implementation : {"opencv", "pgba"}) {
    SiftOptions opt;
    opt.implementation = implementation;
    opt.max_image_size = 0;
    const FeatureSet f = ExtractSift(img, opt);
    ASSERT_GE(f.size(), 1u) << implementation;
    const Keypoint& k = f.keypoints[0];
    std::cout << implementation << ": blob at (" << k.x << ", " << k.y << ") scale " << k.scale << ", expected ("
              << cx + 0.5 << ", " << cy + 0.5 << ") scale " << expected_scale << "\n";
    EXPECT_NEAR(k.x, cx + 0.5, 0.05) << implementation;
    EXPECT_NEAR(k.y, cy + 0.5, 0.05) << implementation;
    EXPECT_NEAR(k.scale / expected_scale, 1.0, 0.03) << implementation;
  }
}

// Fraction of the keypoints of `a` inside `b`'s frame whose position mapped by the 2x3
// similarity A (COLMAP pixel coordinates) has a keypoint of `b` within 1.5 px and of the
// mapped scale within a factor sqrt(2): the detector's repeatability (Mikolajczyk et al.).
double Repeatability(const FeatureSet& a, const FeatureSet& b, const cv::Matx23d& A, double zoom) {
  int inside = 0, repeated = 0;
  for (const Keypoint& k : a.keypoints) {
    const double x = A(0, 0) * k.x + A(0, 1) * k.y + A(0, 2), y = A(1, 0) * k.x + A(1, 1) * k.y + A(1, 2);
    if (x < 20 || y < 20 || x > b.width - 20 || y > b.height - 20) continue;
    ++inside;
    const double s = k.scale * zoom;
    for (const Keypoint& q : b.keypoints)
      if (std::hypot(q.x - x, q.y - y) < 1.5 && q.scale < 1.42 * s && s < 1.42 * q.scale) {
        ++repeated;
        break;
      }
  }
  return inside > 0 ? static_cast<double>(repeated) / inside : 0.0;
}

TEST(SiftExtractor, RepeatabilityUnderKnownZoomAndRotation) {
  // The image and its copy rotated by 15 degrees and zoomed out 0.8x about its centre (a
  // known similarity, the truth), with pgba's SIFT: the upsampled first octave repeats more
  // keypoints than starting at the image's resolution, whose finest scales are missing in
  // the zoomed-out copy; that measured cost is why first_octave 0 is only an option.
  const cv::Mat img = TexturedImage(900, 700, 4);
  const cv::Point2f centre(450.f, 350.f);
  const cv::Mat A_cv = cv::getRotationMatrix2D(centre, 15.0, 0.8);  // integer-centre pixels
  cv::Mat warped;
  cv::warpAffine(img, warped, A_cv, img.size(), cv::INTER_CUBIC);
  // The same map in COLMAP coordinates: x_colmap = x_cv + 0.5 on both sides.
  cv::Matx23d A(A_cv.ptr<double>(0));
  A(0, 2) += 0.5 - 0.5 * (A(0, 0) + A(0, 1));
  A(1, 2) += 0.5 - 0.5 * (A(1, 0) + A(1, 1));
  double rep[2];
  for (int first_octave : {-1, 0}) {
    SiftOptions opt;
    opt.implementation = "pgba";
    opt.max_features = 2000;
    opt.first_octave = first_octave;
    rep[first_octave + 1] = Repeatability(ExtractSift(img, opt), ExtractSift(warped, opt), A, 0.8);
  }
  // The same with OpenCV's SIFT (first octave -1), the implementation pgba's replaced.
  SiftOptions cv_opt;
  cv_opt.max_features = 2000;
  cv_opt.implementation = "opencv";
  const double rep_cv = Repeatability(ExtractSift(img, cv_opt), ExtractSift(warped, cv_opt), A, 0.8);
  std::cout << "repeatability: first_octave -1 " << rep[0] << ", 0 " << rep[1] << "; opencv " << rep_cv << std::endl;
  // Measured (pgba's SIFT): 0.83 and 0.43; OpenCV's 0.83 (it gave 0.48 at first octave 0,
  // through the image halved and doubled).
  EXPECT_GT(rep[0], 0.78);
  EXPECT_GT(rep[1], 0.38);
  EXPECT_GT(rep[0], rep[1] + 0.25);
  EXPECT_GE(rep[0], rep_cv - 0.005);
}

TEST(SiftExtractor, AdaptiveContrastReachesTheTargetWithRepeatableKeypoints) {
  // A low-contrast copy of the textured image (grey levels 110-141, as plaster under soft
  // light) and the same copy under the known zoom + rotation: at the fixed threshold few
  // keypoints survive; the adaptive detection lowers the threshold until the target is
  // reached (or the floor), and its keypoints repeat under the known map about as well as
  // those of the full-contrast image in RepeatabilityUnderKnownZoomAndRotation (0.83).
  cv::Mat img = TexturedImage(480, 360, 5);
  img.convertTo(img, CV_8U, 32.0 / 256.0, 110.0);
  const cv::Point2f centre(240.f, 180.f);
  const cv::Mat A_cv = cv::getRotationMatrix2D(centre, 15.0, 0.8);
  cv::Mat warped;
  cv::warpAffine(img, warped, A_cv, img.size(), cv::INTER_CUBIC, cv::BORDER_REPLICATE);
  cv::Matx23d A(A_cv.ptr<double>(0));
  A(0, 2) += 0.5 - 0.5 * (A(0, 0) + A(0, 1));
  A(1, 2) += 0.5 - 0.5 * (A(1, 0) + A(1, 1));

  SiftOptions fixed;
  const FeatureSet f = ExtractSift(img, fixed);
  EXPECT_FLOAT_EQ(f.contrast_threshold, static_cast<float>(fixed.contrast_threshold));
  SiftOptions adaptive = fixed;
  adaptive.target_features = 1000;
  const FeatureSet a = ExtractSift(img, adaptive);
  const double rep_adaptive = Repeatability(a, ExtractSift(warped, adaptive), A, 0.8);
  std::cout << "low contrast: fixed " << f.size() << " keypoints, adaptive " << a.size() << " at contrast "
            << a.contrast_threshold << " (repeatability " << rep_adaptive << ")" << std::endl;
  ASSERT_LT(f.size(), 200u);
  EXPECT_TRUE(a.size() >= 1000u || a.contrast_threshold / 2 < adaptive.min_contrast_threshold);
  EXPECT_LT(a.contrast_threshold, f.contrast_threshold);
  EXPECT_GT(a.size(), 4 * f.size());
  EXPECT_GT(rep_adaptive, 0.7);

  // A textured image reaches the target at the first threshold: nothing changes.
  SiftOptions few = adaptive;
  few.target_features = 200;
  const FeatureSet t = ExtractSift(TexturedImage(480, 360, 5), few);
  EXPECT_FLOAT_EQ(t.contrast_threshold, static_cast<float>(fixed.contrast_threshold));

  SiftOptions bad = adaptive;
  bad.min_contrast_threshold = 0.1;
  EXPECT_THROW(ExtractSift(img, bad), InputError);
}

TEST(SiftExtractor, RootSiftIsHellingerNormalisedAndCapped) {
  const cv::Mat img = TexturedImage(400, 300, 2);
  SiftOptions opt;
  opt.max_features = 150;
  opt.root_sift = true;
  const FeatureSet root = ExtractSift(img, opt);
  opt.root_sift = false;
  const FeatureSet plain = ExtractSift(img, opt);
  ASSERT_EQ(root.size(), 150u);
  ASSERT_EQ(plain.size(), 150u);
  for (size_t i = 0; i < root.size(); ++i) {
    // Same keypoints, only the descriptor normalisation differs.
    EXPECT_EQ(root.keypoints[i].x, plain.keypoints[i].x);
    // RootSIFT = sqrt(L1-normalised SIFT): unit L2 norm (on the 512 scale, up to rounding
    // and saturation at 255).
    double sq = 0, l1 = 0, root_sq = 0;
    for (int k = 0; k < kSiftDescriptorSize; ++k) {
      const double r = root.descriptors.at<uint8_t>(i, k) / 512.0;
      root_sq += r * r;
      l1 += plain.descriptors.at<uint8_t>(i, k);
      sq += std::pow(plain.descriptors.at<uint8_t>(i, k), 2);
    }
    EXPECT_NEAR(root_sq, 1.0, 0.03) << i;
    // Plain SIFT is L2-normalised to 512 (then clipped), not L1: its sqrt-L1 norm differs.
    EXPECT_NEAR(std::sqrt(sq), 512.0, 30.0) << i;
    // The stored plain value p is the float rounded: the float was in [p - 0.5, p + 0.5],
    // so RootSIFT's is between the roots of those bounds (4 of slack for l1 being summed
    // from rounded values; a near-zero float, stored 0, can have a root of ~5).
    for (int k = 0; k < kSiftDescriptorSize; ++k) {
      const double p = plain.descriptors.at<uint8_t>(i, k);
      const double lo = 512.0 * std::sqrt(std::max(0.0, p - 0.5) / l1), hi = 512.0 * std::sqrt((p + 0.5) / l1);
      EXPECT_GE(root.descriptors.at<uint8_t>(i, k), std::min(255.0, lo) - 4.0) << i << " " << k;
      EXPECT_LE(root.descriptors.at<uint8_t>(i, k), std::min(255.0, hi) + 4.0) << i << " " << k;
    }
  }
  // Strongest first: max_features keeps a prefix of the uncapped order.
  opt.max_features = 60;
  const FeatureSet fewer = ExtractSift(img, opt);
  ASSERT_EQ(fewer.size(), 60u);
  for (size_t i = 0; i < fewer.size(); ++i) EXPECT_EQ(fewer.keypoints[i].x, plain.keypoints[i].x);
}

TEST(FeatureFile, RoundTripAndDamage) {
  const FeatureSet f = ExtractSift(TexturedImage(200, 150, 3), SiftOptions{});
  ASSERT_GT(f.size(), 10u);
  const fs::path dir = fs::temp_directory_path() / ("pgba_featfile_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / "a.bin").string();
  WriteFeatureFile(path, f, "key-1");
  std::string key;
  const FeatureSet g = ReadFeatureFile(path, &key);
  EXPECT_EQ(key, "key-1");
  EXPECT_EQ(g.width, 200);
  EXPECT_EQ(g.height, 150);
  EXPECT_EQ(g.contrast_threshold, f.contrast_threshold);
  ASSERT_EQ(g.size(), f.size());
  for (size_t i = 0; i < f.size(); ++i) {
    EXPECT_EQ(g.keypoints[i].x, f.keypoints[i].x);
    EXPECT_EQ(g.keypoints[i].orientation, f.keypoints[i].orientation);
  }
  EXPECT_EQ(cv::norm(g.descriptors, f.descriptors, cv::NORM_L1), 0.0);

  // Truncated: every shorter prefix is an InputError, never a crash.
  const std::uintmax_t size = fs::file_size(path);
  for (std::uintmax_t cut : {size - 1, size / 2, std::uintmax_t{20}, std::uintmax_t{3}}) {
    fs::copy_file(path, dir / "t.bin", fs::copy_options::overwrite_existing);
    fs::resize_file(dir / "t.bin", cut);
    EXPECT_THROW(ReadFeatureFile((dir / "t.bin").string()), InputError) << cut;
  }
  std::ofstream(dir / "junk.bin") << "not a feature file at all";
  EXPECT_THROW(ReadFeatureFile((dir / "junk.bin").string()), InputError);
  EXPECT_THROW(ReadFeatureFile((dir / "missing.bin").string()), InputError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pgba
