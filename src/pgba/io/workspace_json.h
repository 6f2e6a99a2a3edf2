// Shared by the readers and writers of the workspace's JSON artefacts (pairs.json,
// triplets.json, motions.json, local_hessians.json): the document layout (format, version, one
// entry per line), poses as {"q": [w, x, y, z], "t": [3]} (COLMAP's q, t = -R c), and a reader
// whose every problem becomes a one-line InputError "FILE: WHERE: problem" (json_file_reader.h).
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pgba/geometry/pose.h"
#include "pgba/io/json_file_reader.h"
#include "pgba/scene/reconstruction.h"

namespace pgba {

namespace internal_workspace {
nlohmann::json RowMajor(const Eigen::Matrix3d& M);
nlohmann::json Array(const Eigen::Vector3d& v);
// The name of image `id` in `tracks` (InputError naming `path` if absent).
const std::string& NameOf(const Reconstruction& tracks, uint32_t id, const std::filesystem::path& path);
nlohmann::json PoseJson(const Pose& pose);  // {"q": [w, x, y, z], "t": [3]}
// "{"format": F, "version": V, HEADER..., "key": [\n entry,\n entry\n]}\n"; `header`: further
// top-level fields (an object) written before the entries.
std::string Document(const char* format, const char* key, const std::vector<nlohmann::json>& entries,
                     const nlohmann::json& header = nlohmann::json::object());
// The same document written to `path` atomically, entry k made by entry(k) only when it is
// written: one entry is in memory at a time (local_hessians.json holds (6N)^2 numbers per
// motion, more than the motions themselves as a JSON tree and its text together).
void WriteDocument(const std::filesystem::path& path, const char* format, const char* key, size_t count,
                   const std::function<nlohmann::json(size_t)>& entry,
                   const nlohmann::json& header = nlohmann::json::object());
}  // namespace internal_workspace

// A workspace artefact: format and version checked, image names resolved in the tracks model.
class WorkspaceJsonReader : public JsonFileReader {
 public:
  WorkspaceJsonReader(const std::filesystem::path& path, const Reconstruction& tracks)
      : JsonFileReader(path.string()), tracks_(tracks) {}

  // Parses the file and checks format and version; returns the entry array `key`.
  nlohmann::json Load(const char* format, const char* key) const;
  // The same, returning the whole document (its header fields and the array `key`).
  nlohmann::json LoadDocument(const char* format, const char* key) const;
  // A pose written by PoseJson: q of unit norm (up to rounding), finite values.
  Pose PoseOf(const nlohmann::json& j, const std::string& where) const;
  Eigen::Matrix3d Rotation(const nlohmann::json& j, const std::string& where) const;
  // The image named `name` in the tracks model; its id must equal the stored one.
  uint32_t Image(const nlohmann::json& name, const nlohmann::json& stored_id, const std::string& where) const;

 private:
  const Reconstruction& tracks_;
};

}  // namespace pgba
