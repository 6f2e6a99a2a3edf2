#include "pgba/io/workspace_json.h"

#include <sstream>

#include "pgba/io/workspace.h"
#include "pgba/util/atomic_file.h"
#include "pgba/util/error.h"

namespace pgba {

using nlohmann::json;
namespace fs = std::filesystem;

namespace internal_workspace {

json RowMajor(const Eigen::Matrix3d& M) {
  json j = json::array();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) j.push_back(M(r, c));
  return j;
}

json Array(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

const std::string& NameOf(const Reconstruction& tracks, uint32_t id, const fs::path& path) {
  auto it = tracks.images.find(id);
  if (it == tracks.images.end())
    ThrowInputError(path.string(), 0, "cannot write image id " + std::to_string(id) + ": not in the tracks model");
  return it->second.name;
}

// "{header, "key": [\n entry,\n entry\n]}\n": one entry per line.
json PoseJson(const Pose& pose) {
  const Eigen::Quaterniond& q = pose.q();
  return {{"q", {q.w(), q.x(), q.y(), q.z()}}, {"t", Array(pose.t())}};
}

namespace {

void StreamDocument(std::ostream& out, const char* format, const char* key, size_t count,
                    const std::function<json(size_t)>& entry, const json& header) {
  out << "{\"format\": \"" << format << "\", \"version\": " << kWorkspaceVersion;
  for (const auto& [name, value] : header.items()) out << ", " << json(name).dump() << ": " << value.dump();
  out << ", \"" << key << "\": [";
  for (size_t k = 0; k < count; ++k) out << (k ? ",\n" : "\n") << entry(k).dump();
  out << "\n]}\n";
}

}  // namespace

std::string Document(const char* format, const char* key, const std::vector<json>& entries, const json& header) {
  std::ostringstream out;
  StreamDocument(out, format, key, entries.size(), [&](size_t k) -> const json& { return entries[k]; }, header);
  return out.str();
}

void WriteDocument(const std::filesystem::path& path, const char* format, const char* key, size_t count,
                   const std::function<json(size_t)>& entry, const json& header) {
  WriteFileAtomically(path, [&](std::ostream& out) { StreamDocument(out, format, key, count, entry, header); });
}

}  // namespace internal_workspace

json WorkspaceJsonReader::Load(const char* format, const char* key) const { return LoadDocument(format, key)[key]; }

json WorkspaceJsonReader::LoadDocument(const char* format, const char* key) const {
  const json doc = Parse();
  if (!doc.is_object()) Fail("", "not a JSON object");
  if (!doc.contains("format") || doc["format"] != format)
    Fail("", std::string("not a ") + format + " file (\"format\" must be \"" + format + "\")");
  if (!doc.contains("version") || !doc["version"].is_number_integer()) Fail("", "missing integer \"version\"");
  if (doc["version"].get<int64_t>() != kWorkspaceVersion)
    Fail("", "workspace version " + doc["version"].dump() + ", this build reads version " +
                 std::to_string(kWorkspaceVersion) + " (re-run the stage)");
  if (!doc.contains(key) || !doc[key].is_array()) Fail("", std::string("missing array \"") + key + "\"");
  return doc;
}

Pose WorkspaceJsonReader::PoseOf(const json& j, const std::string& where) const {
  const Eigen::Vector4d q = Numbers<4>(Field(j, "q", where), where + ".q");
  if (!(q.norm() > 0.5 && q.norm() < 2.0)) Fail(where, "quaternion is not unit");
  return Pose::FromQt(Eigen::Quaterniond(q(0), q(1), q(2), q(3)), Numbers<3>(Field(j, "t", where), where + ".t"));
}

Eigen::Matrix3d WorkspaceJsonReader::Rotation(const json& j, const std::string& where) const {
  const Eigen::Matrix<double, 9, 1> v = Numbers<9>(j, where);
  Eigen::Matrix3d R;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R(r, c) = v(3 * r + c);
  if ((R * R.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-6 || R.determinant() < 0)
    Fail(where, "not a rotation matrix");
  return R;
}

uint32_t WorkspaceJsonReader::Image(const json& name, const json& stored_id, const std::string& where) const {
  if (!name.is_string()) Fail(where, "image name must be a string");
  const std::optional<uint32_t> id = tracks_.FindImageByName(name.get<std::string>());
  if (!id) Fail(where, "unknown image name '" + name.get<std::string>() + "' (workspace of another model?)");
  if (Integer(stored_id, where) != static_cast<int64_t>(*id))
    Fail(where, "image '" + name.get<std::string>() + "' has id " + std::to_string(*id) +
                    " in the tracks model but " + stored_id.dump() + " in the workspace");
  return *id;
}

}  // namespace pgba
