#include "pgba/io/workspace_fingerprint.h"

#include "pgba/io/json_file_reader.h"
#include "pgba/util/atomic_file.h"
#include "pgba/util/checksum.h"
#include "pgba/util/error.h"

namespace pgba {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kFormat = "pgba_fingerprint";
constexpr int kVersion = 1;

template <typename T>
uint64_t Mix(const T& value, uint64_t hash) {
  return Fnv1a64(&value, sizeof(T), hash);
}

// The first difference between two option objects, as "key: A there, B here".
std::string FirstDifference(const json& stored, const json& current) {
  const json patch = json::diff(stored, current);
  if (patch.empty()) return "";
  const std::string path = patch[0].value("path", "");
  std::string key = path.substr(path.empty() ? 0 : 1);
  for (char& c : key)
    if (c == '/') c = '.';
  const json::json_pointer pointer(path);
  const std::string there = stored.contains(pointer) ? stored.at(pointer).dump() : "(absent)";
  const std::string here = current.contains(pointer) ? current.at(pointer).dump() : "(absent)";
  return key + ": " + there + " there, " + here + " here";
}

}  // namespace

fs::path WorkspaceFingerprintPath(const fs::path& workspace) { return workspace / "fingerprint.json"; }

std::string TracksFingerprint(const Reconstruction& tracks) {
  uint64_t h = kFnv1a64Offset;
  for (const auto& [id, cam] : tracks.cameras) {
    h = Mix(id, h);
    h = Mix(static_cast<int>(cam.model), h);
    h = Mix(cam.width, h);
    h = Mix(cam.height, h);
    for (double p : cam.params) h = Mix(p, h);
  }
  for (const auto& [id, im] : tracks.images) {
    h = Mix(id, h);
    h = Mix(im.camera_id, h);
    h = Fnv1a64(im.name + '\0', h);
    h = Mix(im.points2D.size(), h);
    for (const auto& p : im.points2D) {
      h = Mix(p.xy.x(), h);
      h = Mix(p.xy.y(), h);
      h = Mix(p.point3D_id, h);
    }
  }
  for (const auto& [id, point] : tracks.points3D) {
    h = Mix(id, h);
    for (const TrackElement& e : point.track) {
      h = Mix(e.image_id, h);
      h = Mix(e.point2D_idx, h);
    }
  }
  return Hex64(h);
}

json WithoutThreadCounts(json options) {
  if (options.is_object()) {
    options.erase("num_threads");
    for (auto& [key, value] : options.items()) value = WithoutThreadCounts(value);
  }
  return options;
}

void WriteWorkspaceFingerprint(const fs::path& workspace, const WorkspaceFingerprint& f) {
  json j = {{"format", kFormat}, {"version", kVersion}, {"tracks", f.tracks}, {"init_options", f.init_options}};
  if (!f.hessian_options.is_null()) j["hessian_options"] = f.hessian_options;
  WriteStringAtomically(WorkspaceFingerprintPath(workspace), j.dump(1) + "\n");
}

void CheckWorkspaceFingerprint(const fs::path& workspace, const WorkspaceFingerprint& expected) {
  const fs::path path = WorkspaceFingerprintPath(workspace);
  std::error_code ec;
  if (!fs::exists(path, ec))
    ThrowInputError(path.string(), 0,
                    "missing: not a workspace of this version of pgba init / reconstruct / run (re-run them)");
  const JsonFileReader reader(path.string());
  const json j = reader.Parse();
  if (!j.is_object() || !j.contains("format") || j.at("format") != kFormat)
    reader.Fail("", "not a pgba workspace fingerprint");
  if (reader.Integer(reader.Field(j, "version", ""), "version") != kVersion) reader.Fail("", "unsupported version");
  const json& tracks = reader.Field(j, "tracks", "");
  if (!tracks.is_string()) reader.Fail("tracks", "expected a string");
  if (tracks.get<std::string>() != expected.tracks)
    reader.Fail("", "the workspace was computed from other tracks (fingerprint " + tracks.get<std::string>() +
                        ", these tracks " + expected.tracks + "): another scene's workspace?");
  const std::string init_diff = FirstDifference(reader.Field(j, "init_options", ""), expected.init_options);
  if (!init_diff.empty())
    reader.Fail("", "the workspace was initialised with other options (" + init_diff +
                        "); re-run without --workspace");
  if (j.contains("hessian_options") && !expected.hessian_options.is_null()) {
    const std::string diff = FirstDifference(j.at("hessian_options"), expected.hessian_options);
    if (!diff.empty())
      reader.Fail("", "the workspace's local hessians were computed with other options (" + diff +
                          "); re-run without --workspace");
  }
}

}  // namespace pgba
