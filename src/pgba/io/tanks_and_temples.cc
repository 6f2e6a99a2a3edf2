#include "pgba/io/tanks_and_temples.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "pgba/io/colmap_text.h"
#include "pgba/util/error.h"
#include "pgba/util/text_reader.h"

namespace pgba {

namespace fs = std::filesystem;

Reconstruction TrajectoryToModel(const std::vector<TrajectoryFrame>& frames, const std::vector<std::string>& names,
                                 const std::map<uint32_t, Camera>& cameras, const std::string& log_path) {
  if (frames.size() != names.size())
    ThrowInputError(log_path, 0,
                    std::to_string(frames.size()) + " frames but " + std::to_string(names.size()) +
                        " images: the trajectory must have one frame per image, in image-name order");
  if (cameras.size() != 1)
    ThrowInputError(log_path, 0,
                    "the calibration has " + std::to_string(cameras.size()) + " cameras; exactly one is needed");
  Reconstruction rec;
  rec.cameras = cameras;
  for (size_t i = 0; i < frames.size(); ++i) {
    Image im;
    im.image_id = static_cast<uint32_t>(i + 1);
    im.name = names[i];
    im.camera_id = cameras.begin()->first;
    im.pose = frames[i].ToPose();
    rec.images[im.image_id] = im;
  }
  return rec;
}

namespace {

bool IsPhoto(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".jpg" || ext == ".jpeg" || ext == ".png";
}

std::vector<std::string> ImageNames(const TanksAndTemplesInput& in) {
  std::vector<std::string> names;
  if (!in.image_list.empty()) {
    TextReader reader(in.image_list);
    std::vector<std::string> tok;
    while (reader.NextLine(&tok)) {
      if (tok.size() != 1) reader.Fail("expected one image name per line");
      if (std::find(names.begin(), names.end(), tok[0]) != names.end())
        reader.Fail("image " + TextReader::Printable(tok[0]) + " listed twice");
      names.push_back(tok[0]);
    }
    return names;
  }
  std::error_code ec;
  if (!fs::is_directory(in.images_dir, ec)) ThrowInputError(in.images_dir, 0, "not a directory");
  // error_code overloads: an entry that cannot be stat'ed (a symlink loop) is named in one
  // line, not a raw filesystem_error.
  fs::directory_iterator it(in.images_dir, ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.empty() || name[0] == '.' || !IsPhoto(it->path())) continue;
    std::error_code stat_error;
    const bool regular = it->is_regular_file(stat_error);
    if (stat_error) ThrowInputError(it->path().string(), 0, "cannot access: " + stat_error.message());
    if (regular) names.push_back(name);
  }
  if (ec) ThrowInputError(in.images_dir, 0, "cannot list the folder: " + ec.message());
  std::sort(names.begin(), names.end());
  if (names.empty()) ThrowInputError(in.images_dir, 0, "no .jpg/.jpeg/.png photo");
  return names;
}

}  // namespace

size_t ConvertTanksAndTemples(const TanksAndTemplesInput& input, const std::string& out,
                              const DatasetLayoutOptions& layout) {
  const std::vector<TrajectoryFrame> frames = ReadTrajectoryLog(input.log_path);
  const std::vector<std::string> names = ImageNames(input);
  const Reconstruction gt = TrajectoryToModel(frames, names, ReadColmapCameras(input.cameras_path), input.log_path);
  std::map<std::string, std::string> sources;
  for (const std::string& n : names) sources[n] = (fs::path(input.images_dir) / n).string();
  WriteDatasetLayout(gt, sources, out, layout);
  return gt.images.size();
}

}  // namespace pgba
