#include "features/image_catalog.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <tuple>

#include "features/exif_focal.h"
#include "pgba/io/calibration_json.h"
#include "pgba/io/colmap_text.h"
#include "pgba/io/input_checks.h"
#include "pgba/util/error.h"
#include "pgba/util/input_file.h"
#include "pgba/util/logging.h"
#include "pgba/util/text_format.h"
#include "pgba/util/text_reader.h"

namespace pgba {
namespace fs = std::filesystem;

namespace {

// The calibration file to use, "" if there is none (then the cameras are priors).
std::string FindCalibration(const fs::path& dir, const std::string& given) {
  if (!given.empty()) {
    RequireRegularFile(given);
    return given;
  }
  // A cameras.txt that is there but no regular file (a FIFO, a device) is refused naming it,
  // not skipped: skipping it would silently run on priors instead of the user's calibration.
  std::error_code ec;
  for (const fs::path& p : {dir / "cameras.txt", dir.parent_path() / "cameras.txt"})
    if (fs::exists(p, ec)) {
      RequireRegularFile(p.string());
      return p.string();
    }
  return "";
}

std::string PriorSourceName(bool any_exif, bool any_default) {
  if (any_exif && any_default) return "exif+default-prior";
  return any_exif ? "exif" : "default-prior";
}

struct DecodedSize {
  int width = 0;  // 0: OpenCV cannot decode the file
  int height = 0;
};

// The size the features stage will see (same decoder and flags), one image per task. OpenCV
// has no header-only size query; a decode costs ~25 ms of CPU per 6 MP JPEG (sceaux_castle),
// about 1% of the SIFT that follows (and is paid again on a re-run with cached features).
std::vector<DecodedSize> DecodeSizes(const fs::path& dir, const std::vector<std::string>& files) {
  std::vector<DecodedSize> sizes(files.size());
  tbb::parallel_for(size_t(0), files.size(), [&](size_t i) {
    const std::string path = (dir / files[i]).string();
    try {
      if (!cv::haveImageReader(path)) return;
      const cv::Mat gray = cv::imread(path, cv::IMREAD_GRAYSCALE | cv::IMREAD_IGNORE_ORIENTATION);
      sizes[i] = {gray.cols, gray.rows};
    } catch (const cv::Exception&) {
      // Left undecodable: the features stage reports it.
    }
  });
  return sizes;
}

// Prior cameras (see the header), one per (width, height, focal), ids in file-name order.
void AssignPriorCameras(const fs::path& dir, ImageCatalog* catalog) {
  const std::vector<DecodedSize> sizes = DecodeSizes(dir, catalog->files);
  std::map<std::tuple<int, int, double>, uint32_t> camera_of_key;
  std::map<uint32_t, FocalSource> source_of;
  std::map<uint32_t, int> num_images;
  for (size_t i = 0; i < catalog->files.size(); ++i) {
    const auto [w, h] = sizes[i];
    if (w <= 0 || h <= 0) continue;
    const std::string path = (dir / catalog->files[i]).string();
    const FocalPrior prior = ExifFocalPrior(path, w, h);
    if (!prior.problem.empty()) PGBA_LOG_WARN << path << ": " << prior.problem << "; using the default focal prior";
    const auto [it, added] = camera_of_key.emplace(std::make_tuple(w, h, prior.focal_px), catalog->cameras.size() + 1);
    if (added) {
      Camera cam;
      cam.camera_id = it->second;
      // COLMAP's default model without a calibration: SIMPLE_RADIAL, k = 0 to start.
      cam.model = CameraModel::kSimpleRadial;
      cam.width = w;
      cam.height = h;
      cam.params = {prior.focal_px, 0.5 * w, 0.5 * h, 0.0};
      cam.has_prior_focal_length = prior.source != FocalSource::kDefault;
      catalog->cameras[cam.camera_id] = cam;
      source_of[cam.camera_id] = prior.source;
    }
    catalog->camera_of[catalog->files[i]] = it->second;
    ++num_images[it->second];
  }
  if (catalog->cameras.empty())
    ThrowInputError(dir.string(), 0,
                    "no calibration (pass --calib cameras.txt; none in the folder or its parent) and no decodable "
                    "image to take a focal prior from");
  for (const std::string& f : catalog->files) catalog->camera_of.emplace(f, 1);  // undecodable: see the header

  bool any_exif = false, any_default = false;
  PGBA_LOG_WARN << "no calibration given: the focal length and lens distortion are estimated from the images "
                   "(pass --calib cameras.txt to use a known calibration)";
  for (const auto& [id, cam] : catalog->cameras) {
    const FocalSource source = source_of.at(id);
    (source == FocalSource::kDefault ? any_default : any_exif) = true;
    const int n = num_images.at(id);
    PGBA_LOG_INFO << "camera " << id << ": " << n << (n == 1 ? " image " : " images ") << cam.width << "x"
                  << cam.height << ", focal " << FormatNumber("%.1f", cam.params[0]) << " px to start "
                  << (source == FocalSource::kDefault ? std::string("(no EXIF focal: 1.2 x the larger side)")
                                                      : std::string("(") + FocalSourceName(source) + ")");
  }
  catalog->calibration_source = PriorSourceName(any_exif, any_default);
}

// Every visible regular file of `dir`, sorted by name. An entry that cannot even be
// stat'ed (a symlink loop, a dangling link, no permission) is skipped with a warning naming
// it, instead of a raw filesystem_error ending the run.
std::vector<std::string> ListFiles(const fs::path& dir) {
  std::vector<std::string> files;
  std::error_code ec;
  fs::directory_iterator it(dir, ec), end;
  if (ec) ThrowInputError(dir.string(), 0, "cannot list the image folder: " + ec.message());
  for (; it != end; it.increment(ec)) {
    if (ec) ThrowInputError(dir.string(), 0, "cannot list the image folder: " + ec.message());
    const std::string name = it->path().filename().string();
    if (name.empty() || name[0] == '.') continue;
    std::error_code stat_error;
    const bool regular = it->is_regular_file(stat_error);
    if (stat_error) {
      PGBA_LOG_WARN << it->path().string() << ": cannot access (" << stat_error.message() << "); skipped";
      continue;
    }
    if (!regular) continue;
    // A name the tracks model (COLMAP text) could not give back as it is: left out here,
    // with the folder named, rather than a model that a later command rejects or misreads.
    if (const std::string problem = CheckImageName(name); !problem.empty()) {
      PGBA_LOG_WARN << dir.string() << ": " << problem << "; skipped (rename the file)";
      continue;
    }
    files.push_back(name);
  }
  if (ec) ThrowInputError(dir.string(), 0, "cannot list the image folder: " + ec.message());
  std::sort(files.begin(), files.end());
  return files;
}

// A JPEG whose last scan (the last SOS marker, FF DA) is not followed by an end-of-image
// marker (FF D9) was cut short: libjpeg decodes it with grey rows and only prints "Premature
// end of JPEG file", naming no file. Entropy-coded data stuffs every FF byte (FF 00), so
// neither marker can occur inside a scan.
bool IsTruncatedJpeg(const std::string& bytes) {
  if (bytes.size() < 3 || static_cast<unsigned char>(bytes[0]) != 0xFF ||
      static_cast<unsigned char>(bytes[1]) != 0xD8 || static_cast<unsigned char>(bytes[2]) != 0xFF)
    return false;  // not a JPEG
  const size_t sos = bytes.rfind("\xFF\xDA");
  if (sos == std::string::npos) return true;  // no image data at all
  return bytes.find("\xFF\xD9", sos + 2) == std::string::npos;
}

void SkipTruncatedJpegs(const fs::path& dir, std::vector<std::string>* files) {
  std::vector<char> truncated(files->size(), 0);
  tbb::parallel_for(size_t(0), files->size(), [&](size_t i) {
    std::ifstream in(dir / (*files)[i], std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    truncated[i] = IsTruncatedJpeg(bytes);
  });
  std::vector<std::string> kept;
  for (size_t i = 0; i < files->size(); ++i) {
    if (truncated[i])
      PGBA_LOG_WARN << (dir / (*files)[i]).string() << ": truncated JPEG (no end-of-image marker after its last scan); skipped";
    else
      kept.push_back((*files)[i]);
  }
  *files = std::move(kept);
}

std::map<std::string, uint32_t> ReadCameraMap(const std::string& path, const std::map<uint32_t, Camera>& cameras) {
  std::map<std::string, uint32_t> map;
  TextReader reader(path);
  std::vector<std::string> tokens;
  while (reader.NextLine(&tokens)) {
    reader.RequireTokens(tokens, 2, "IMAGE_NAME CAMERA_ID");
    const int64_t id = reader.ToInt(tokens[1], "CAMERA_ID");
    if (id < 0 || id > static_cast<int64_t>(UINT32_MAX) || !cameras.count(static_cast<uint32_t>(id)))
      reader.Fail("camera " + tokens[1] + " is not in the calibration");
    if (!map.emplace(tokens[0], static_cast<uint32_t>(id)).second) reader.Fail("image " + tokens[0] + " listed twice");
  }
  return map;
}

}  // namespace

ImageCatalog BuildImageCatalog(const std::string& images_dir, const CalibrationInput& calibration) {
  RequireDirectory(images_dir, "image folder", "a folder of photos");
  const fs::path dir = fs::weakly_canonical(images_dir);  // no trailing '/': parent_path() is the parent
  ImageCatalog catalog;
  catalog.files = ListFiles(dir);
  if (catalog.files.empty()) ThrowInputError(images_dir, 0, "image folder is empty");
  SkipTruncatedJpegs(dir, &catalog.files);
  if (catalog.files.empty()) ThrowInputError(images_dir, 0, "image folder has no usable file (see the warnings)");

  catalog.cameras_path = FindCalibration(dir, calibration.cameras_path);
  if (catalog.cameras_path.empty()) {
    if (!calibration.camera_map_path.empty())
      ThrowInputError(calibration.camera_map_path, 0,
                      "a camera map needs a calibration file (--calib cameras.txt); none given or found");
    AssignPriorCameras(dir, &catalog);
    return catalog;
  }
  catalog.calibration_source = "file: " + catalog.cameras_path;
  std::map<std::string, uint32_t> json_camera_of;
  if (fs::path(catalog.cameras_path).extension() == ".json") {
    CalibrationFile file = ReadCalibrationJson(catalog.cameras_path);
    catalog.cameras = std::move(file.cameras);
    json_camera_of = std::move(file.camera_of);
  } else {
    catalog.cameras = ReadColmapCameras(catalog.cameras_path);
  }
  if (catalog.cameras.empty()) ThrowInputError(catalog.cameras_path, 0, "calibration has no camera");
  for (const auto& [id, cam] : catalog.cameras) {
    const std::string problem = CheckCamera(cam);
    if (!problem.empty()) ThrowInputError(catalog.cameras_path, 0, "camera " + std::to_string(id) + ": " + problem);
  }

  if (!calibration.camera_map_path.empty()) {
    catalog.camera_of = ReadCameraMap(calibration.camera_map_path, catalog.cameras);
  } else if (!json_camera_of.empty()) {
    catalog.camera_of = std::move(json_camera_of);
  } else if (catalog.cameras.size() == 1) {
    for (const std::string& f : catalog.files) catalog.camera_of[f] = catalog.cameras.begin()->first;
  } else {
    ThrowInputError(catalog.cameras_path, 0,
                    std::to_string(catalog.cameras.size()) +
                        " cameras: pass a camera map (lines \"IMAGE_NAME CAMERA_ID\") to say which image uses which");
  }
  return catalog;
}

}  // namespace pgba
