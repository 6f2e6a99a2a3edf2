#include "pgba/io/dataset_layout.h"

#include <filesystem>

#include "pgba/io/colmap_text.h"
#include "pgba/util/atomic_file.h"
#include "pgba/util/error.h"

namespace pgba {

namespace fs = std::filesystem;

void WriteDatasetLayout(const Reconstruction& gt, const std::map<std::string, std::string>& sources,
                        const std::string& out, const DatasetLayoutOptions& options) {
  Reconstruction poses;
  poses.cameras = gt.cameras;
  for (const auto& [id, im] : gt.images) {
    Image copy = im;
    copy.points2D.clear();
    poses.images[id] = copy;
    const auto src = sources.find(im.name);
    if (src == sources.end()) throw InputError("dataset conversion: no source photo for image '" + im.name + "'");
    if (fs::path(im.name).filename().string() != im.name || im.name.empty() || im.name[0] == '.')
      throw InputError("dataset conversion: image name '" + im.name + "' is not a plain file name");
    std::error_code ec;
    if (!fs::is_regular_file(src->second, ec))
      throw InputError(src->second + ": photo of image '" + im.name + "' not found");
  }
  const fs::path root(out);
  const fs::path images = root / "images";
  std::error_code ec;
  fs::create_directories(images, ec);
  if (ec) throw InputError(images.string() + ": cannot create directory: " + ec.message());
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
    if (ec) throw InputError(dst.string() + ": cannot " + (options.copy_images ? "copy" : "link") + " " + src.string() +
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
