#include "features/extract_features.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <optional>

#include "features/buffer_pool.h"
#include "features/feature_file.h"
#include "pgba/io/option_ranges.h"
#include "pgba/util/checksum.h"
#include "pgba/util/error.h"
#include "pgba/util/input_file.h"
#include "pgba/util/logging.h"
#include "pgba/util/progress.h"
#include "pgba/util/text_format.h"
#include "pgba/util/timer.h"

namespace pgba {
namespace fs = std::filesystem;

namespace {

// Per-file outcome, written into a preallocated slot by whichever thread handled the file.
struct FileOutcome {
  bool ok = false;
  bool cached = false;
  std::string reason;  // why it was skipped
  int width = 0;
  int height = 0;
  int num_features = 0;
  float contrast_threshold = 0.f;  // where detection ended (FeatureSet::contrast_threshold)
};

// The cache key: extraction options plus a hash of the source file's bytes. Not its size and
// modification time: a photo replaced by another of the same size with the same time
// (cp -p) would reuse the old features.
std::string CacheKey(const fs::path& file, const SiftOptions& sift) {
  const std::string bytes = ReadRegularFile(file.string());
  return SiftOptionsKey(sift) + " src=" + std::to_string(bytes.size()) + ":fnv1a64:" + Hex64(Fnv1a64(bytes));
}

std::string SizeMismatch(int w, int h, const Camera& cam) {
  return "image is " + std::to_string(w) + "x" + std::to_string(h) + " but camera " + std::to_string(cam.camera_id) +
         " is " + std::to_string(cam.width) + "x" + std::to_string(cam.height);
}

FileOutcome ProcessFile(const fs::path& file, const std::string& feature_path, const Camera* camera,
                        const FeatureExtractionOptions& options, std::string* cache_warning) {
  FileOutcome r;
  if (camera == nullptr) {
    r.reason = "no camera for this image in the camera map";
    return r;
  }
  // "auto" resolved by the camera's size, which the decoded image must have: the key names
  // the SIFT that runs (OpenCV's keeps its old key, so caches stay valid).
  const SiftOptions sift = SiftOptionsForImage(options.sift, camera->width, camera->height);
  const std::string key = CacheKey(file, sift);
  if (options.use_cache && fs::exists(feature_path)) {
    try {
      std::string stored;
      FeatureSet cached = ReadFeatureFile(feature_path, &stored);
      if (stored == key) {
        r.cached = true;
        r.width = cached.width;
        r.height = cached.height;
        r.num_features = static_cast<int>(cached.size());
        r.contrast_threshold = cached.contrast_threshold;
      }
    } catch (const InputError& e) {
      *cache_warning = std::string(e.what()) + "; recomputing";
    }
  }
  if (!r.cached) {
    if (!cv::haveImageReader(file.string())) {
      r.reason = "not an image file";
      return r;
    }
    // Stored pixel order (EXIF orientation ignored): calibrations refer to the raw pixels.
    const cv::Mat gray = cv::imread(file.string(), cv::IMREAD_GRAYSCALE | cv::IMREAD_IGNORE_ORIENTATION);
    if (gray.empty()) {
      r.reason = "cannot decode image (corrupt or unsupported)";
      return r;
    }
    r.width = gray.cols;
    r.height = gray.rows;
    if (r.width != camera->width || r.height != camera->height) {
      r.reason = SizeMismatch(r.width, r.height, *camera);
      return r;
    }
    const FeatureSet features = ExtractSift(gray, sift);
    r.num_features = static_cast<int>(features.size());
    r.contrast_threshold = features.contrast_threshold;
    WriteFeatureFile(feature_path, features, key);
  } else if (r.width != camera->width || r.height != camera->height) {
    r.reason = SizeMismatch(r.width, r.height, *camera);
    return r;
  }
  r.ok = true;
  return r;
}

}  // namespace

std::string FeatureExtractionOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "features"); !m.empty()) return m;
  if (const std::string m = sift.Check(); !m.empty()) return "sift." + m;
  return "";
}

FeatureExtractionResult ExtractFeatures(const std::string& images_dir, const CalibrationInput& calibration,
                                        const std::string& workspace, const FeatureExtractionOptions& options) {
  Timer timer;
  if (const std::string problem = options.Check(); !problem.empty()) throw InputError("features." + problem);
  const ImageCatalog catalog = BuildImageCatalog(images_dir, calibration);
  fs::create_directories(FeaturesDir(workspace));

  const size_t n = catalog.files.size();
  std::vector<FileOutcome> outcomes(n);
  std::vector<std::string> cache_warnings(n);
  ProgressBar progress("features", n);
  // One image per task; OpenCV's SIFT parallelises internally through the same TBB
  // scheduler (Debian's OpenCV is built on TBB), so both levels share the cores instead of
  // oversubscribing them. Measured on fountain_p11 (11 images at 1600 px, 2 cores): CPU time
  // is the same whether OpenCV's threading is on or set to 1, or images run one at a time;
  // the parallel loop wins on wall time. `isolate` stops a thread that waits inside
  // OpenCV from picking up another whole image, which bounds memory to one SIFT pyramid per
  // arena thread (~400 MB at 1600 px, ~1.5 GB at 3200 px); max_parallel_images lowers it.
  tbb::task_arena arena(options.max_parallel_images > 0 ? options.max_parallel_images : tbb::task_arena::automatic);
  // pgba's SIFT is parallel inside one image (pyramid rows, extrema blocks, descriptors), so
  // by default its images go one at a time: one scale space in memory instead of one per
  // core, and on the project's VM the first touch of fresh memory (the kernel zeroing pages
  // the host backs lazily, ~2 s per GB) was the largest single cost of the first images.
  // So when every image gets pgba's ("auto" resolved by each camera's size).
  bool all_pgba = n > 0;
  for (const std::string& name : catalog.files) {
    const auto it = catalog.camera_of.find(name);
    if (it == catalog.camera_of.end()) continue;  // skipped below
    const Camera& camera = catalog.cameras.at(it->second);
    all_pgba = all_pgba && SiftOptionsForImage(options.sift, camera.width, camera.height).implementation == "pgba";
  }
  const bool one_at_a_time = options.max_parallel_images <= 0 && all_pgba;
  // The scale-space buffers of a finished image serve the next one (buffer_pool.h): up to
  // one 6 MP image's worth (~2 GiB at the 2x upsampled octave) per image in flight.
  std::optional<ScopedImageBufferPool> buffer_pool;
  if (options.reuse_buffers)
    buffer_pool.emplace((size_t(2) << 30) * static_cast<size_t>(one_at_a_time ? 1 : arena.max_concurrency()));
  const size_t grain = one_at_a_time ? n + 1 : 1;
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, grain), [&](const tbb::blocked_range<size_t>& range) {
     for (size_t i = range.begin(); i < range.end(); ++i) {
      const std::string& name = catalog.files[i];
      const auto it = catalog.camera_of.find(name);
      const Camera* camera = it == catalog.camera_of.end() ? nullptr : &catalog.cameras.at(it->second);
      try {
        tbb::this_task_arena::isolate([&] {
          outcomes[i] = ProcessFile(fs::path(images_dir) / name, FeatureFilePath(workspace, name), camera, options,
                                    &cache_warnings[i]);
        });
      } catch (const cv::Exception& e) {
        outcomes[i] = FileOutcome{};
        outcomes[i].reason = std::string("OpenCV failed: ") + e.what();
      }
      progress.Increment();
     }
    });
  });
  progress.Finish();

  // Warnings and ids in name order, independent of thread scheduling.
  FeatureExtractionResult result;
  result.index.cameras = catalog.cameras;
  result.calibration_source = catalog.calibration_source;
  for (size_t i = 0; i < n; ++i) {
    const std::string file = (fs::path(images_dir) / catalog.files[i]).string();
    if (!cache_warnings[i].empty()) PGBA_LOG_WARN << cache_warnings[i];
    const FileOutcome& o = outcomes[i];
    if (!o.ok) {
      PGBA_LOG_WARN << file << ": " << o.reason << "; skipped";
      result.skipped.push_back({catalog.files[i], o.reason});
      continue;
    }
    IndexedImage im;
    im.image_id = static_cast<uint32_t>(result.index.images.size() + 1);
    im.name = catalog.files[i];
    im.camera_id = catalog.camera_of.at(im.name);
    im.width = o.width;
    im.height = o.height;
    im.num_features = o.num_features;
    im.detection_scale = DetectionScale(o.width, o.height, options.sift);
    result.index.images.push_back(im);
    if (o.contrast_threshold < static_cast<float>(options.sift.contrast_threshold))
      result.adapted_contrast.push_back({im.name, o.contrast_threshold});
    if (o.cached) {
      ++result.num_cached;
    } else {
      ++result.num_extracted;
      result.megapixels_extracted += 1e-6 * o.width * o.height;
    }
  }
  if (result.index.images.empty())
    ThrowInputError(images_dir, 0, "no usable image (" + std::to_string(result.skipped.size()) + " files skipped)");
  WriteFeatureIndex(workspace, result.index);
  result.seconds = timer.Seconds();
  long total = 0;
  for (const IndexedImage& im : result.index.images) total += im.num_features;
  PGBA_LOG_INFO << "features: " << result.index.images.size() << " images, "
                << total / static_cast<long>(result.index.images.size()) << " SIFT features per image on average ("
                << result.num_extracted << " extracted, " << result.num_cached << " from the cache"
                << (result.skipped.empty() ? "" : ", " + std::to_string(result.skipped.size()) + " files skipped")
                << "), " << FormatNumber("%.1f", result.seconds) << " s";
  // Below a few hundred features an image rarely verifies against another one.
  const long mean = total / static_cast<long>(result.index.images.size());
  if (mean < 500 && options.sift.target_features == 0)
    PGBA_LOG_WARN << "few features (" << mean << " per image on average): weakly textured or small images match "
                  << "poorly; features.sift.target_features (as in configs/object_ring.json) detects more";
  return result;
}

nlohmann::json FeatureExtractionRecord(const FeatureExtractionResult& r) {
  nlohmann::json record = {{"images", r.index.images.size()},
                           {"images_extracted", r.num_extracted},
                           {"images_cached", r.num_cached},
                           {"megapixels_extracted", r.megapixels_extracted},
                           {"calibration_source", r.calibration_source}};
  if (r.megapixels_extracted > 0) record["seconds_per_megapixel"] = r.seconds / r.megapixels_extracted;
  nlohmann::json skipped = nlohmann::json::array();
  for (const SkippedImage& s : r.skipped) skipped.push_back({{"name", s.name}, {"reason", s.reason}});
  record["images_skipped"] = skipped;
  long total = 0;
  for (const IndexedImage& im : r.index.images) total += im.num_features;
  if (!r.index.images.empty()) record["features_mean"] = static_cast<double>(total) / r.index.images.size();
  nlohmann::json adapted = nlohmann::json::object();
  for (const auto& [name, c] : r.adapted_contrast) adapted[name] = c;
  record["adapted_contrast_threshold"] = adapted;
  return record;
}

}  // namespace pgba
