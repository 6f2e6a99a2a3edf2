#include "pgba/io/dataset_layout.h"

#include <filesystem>

#include "pgba/io/colmap_text.h"
#include "pgba/io/image_header.h"
#include "pgba/io/input_checks.h"
#include "pgba/util/output_path.h"
#include "pgba/util/atomic_file.h"
#include "pgba/util/error.h"

namespace pgba {

namespace fs = std::filesystem;

const std::vector<std::string> kDatasetLayoutEntries = {"images", "cameras.txt", "camera_map.txt", "gt"};

void WriteDatasetLayout(const Reconstruction& gt, const std::map<std::string, std::string>& sources,
                        const std::string& out, const DatasetLayoutOptions& options) {
  RequireOutputPath(out, "--out");
  Reconstruction poses;
  poses.cameras = gt.cameras;
  for (const auto& [id, cam] : gt.cameras)
    if (const std::string problem = CheckCamera(cam); !problem.empty())
      throw InputError("dataset conversion: camera " + std::to_string(id) + ": " + problem);
  std::vector<NamedInput> photos;
  std::map<std::string, uint32_t> id_of_name;
  for (const auto& [id, im] : gt.images) {
    Image copy = im;
    copy.points2D.clear();
    poses.images[id] = copy;
    if (const std::string problem = CheckImageName(im.name); !problem.empty())
      throw InputError("dataset conversion: image " + std::to_string(id) + ": " + problem);
    const auto src = sources.find(im.name);
    if (src == sources.end()) throw InputError("dataset conversion: no source photo for image " + QuotedName(im.name));
    if (fs::path(im.name).filename().string() != im.name || im.name[0] == '.')
      throw InputError("dataset conversion: image name " + QuotedName(im.name) + " is not a plain file name");
    if (const auto [named, fresh] = id_of_name.emplace(im.name, id); !fresh)
      ThrowInputError(src->second, 0, "listed twice (images " + std::to_string(named->second) + " and " +
                       std::to_string(id) + ")");
    std::error_code ec;
    if (!fs::is_regular_file(src->second, ec))
      ThrowInputError(src->second, 0, "photo of image " + QuotedName(im.name) + " not found");
    const auto cam = gt.cameras.find(im.camera_id);
    if (cam == gt.cameras.end())
      throw InputError("dataset conversion: image " + QuotedName(im.name) + " uses unknown camera " +
                       std::to_string(im.camera_id));
    const std::pair<int, int> size = ReadImageSize(src->second);
    if (size.first != cam->second.width || size.second != cam->second.height)
      ThrowInputError(src->second, 0,
                      "photo is " + std::to_string(size.first) + "x" + std::to_string(size.second) + " but camera " +
                          std::to_string(im.camera_id) + " is " + std::to_string(cam->second.width) + "x" +
                          std::to_string(cam->second.height) + ": the calibration does not belong to these photos");
    photos.push_back({"photo", src->second});
  }
  CheckOutputDirApartFromInputs(out, kDatasetLayoutEntries, photos);
  const fs::path root(out);
  const fs::path images = root / "images";
  std::error_code ec;
  fs::create_directories(images, ec);
  if (ec) ThrowInputError(images.string(), 0, "cannot create directory: " + ec.message());
  for (const auto& [id, im] : poses.images) {
    const fs::path dst = images / im.name;
    const fs::path src = fs::absolute(sources.at(im.name));
    // Staged under a temporary name and renamed over dst: a re-run replaces links atomically.
    const fs::path tmp = images / ("." + im.name + ".tmp");
    fs::remove(tmp, ec);
    if (options.copy_images)
      fs::copy_file(src, tmp, ec);
    else
      fs::create_symlink(src, tmp, ec);
    if (!ec) fs::rename(tmp, dst, ec);
    if (ec) ThrowInputError(dst.string(), 0, std::string("cannot ") + (options.copy_images ? "copy" : "link") + " " + src.string() +
                             ": " + ec.message());
  }
  WriteColmapCamerasFile(poses, (root / "cameras.txt").string());
  if (poses.cameras.size() > 1) {
    WriteFileAtomically(root / "camera_map.txt", [&](std::ostream& s) {
      s << "# IMAGE_NAME CAMERA_ID\n";
      for (const auto& [id, im] : poses.images) s << im.name << ' ' << im.camera_id << '\n';
    });
  } else {
    fs::remove(root / "camera_map.txt", ec);  // an earlier conversion's map would be stale
  }
  WriteColmapText(poses, (root / "gt").string());
}

std::string DatasetLayoutOptions::Check() const {
  return "";  // a switch: every value is valid
}

}  // namespace pgba
