#include "pgba/io/ply.h"

#include <cstring>
#include <ostream>
#include <vector>

#include "pgba/util/atomic_file.h"

namespace pgba {

namespace {

struct Vertex {
  Eigen::Vector3d xyz;
  Eigen::Matrix<uint8_t, 3, 1> rgb;
};

// PLY binary_little_endian: write native bytes, swap on big-endian hosts.
template <typename T>
void PutLittleEndian(std::ostream& out, T v) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &v, sizeof(T));
  const uint16_t probe = 1;
  if (*reinterpret_cast<const unsigned char*>(&probe) != 1)
    for (size_t k = 0; k < sizeof(T) / 2; ++k) std::swap(bytes[k], bytes[sizeof(T) - 1 - k]);
  out.write(reinterpret_cast<const char*>(bytes), sizeof(T));
}

}  // namespace

void WritePly(const Reconstruction& rec, const std::string& path, const PlyOptions& options) {
  std::vector<Vertex> vertices;
  vertices.reserve(rec.points3D.size() + rec.images.size());
  for (const auto& [id, p] : rec.points3D) vertices.push_back({p.xyz, p.color});
  const size_t num_points = vertices.size();
  if (options.camera_centers)
    for (const auto& [id, im] : rec.images) vertices.push_back({im.pose.C(), options.camera_color});

  WriteFileAtomically(path, [&](std::ostream& out) {
    out << "ply\n"
        << "format " << (options.binary ? "binary_little_endian" : "ascii") << " 1.0\n"
        << "comment pgba points " << num_points << " cameras " << vertices.size() - num_points << "\n"
        << "element vertex " << vertices.size() << "\n"
        << "property double x\nproperty double y\nproperty double z\n"
        << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
        << "end_header\n";
    if (options.binary) {
      for (const Vertex& v : vertices) {
        for (int k = 0; k < 3; ++k) PutLittleEndian(out, v.xyz(k));
        for (int k = 0; k < 3; ++k) PutLittleEndian(out, v.rgb(k));
      }
    } else {
      out.precision(17);
      for (const Vertex& v : vertices)
        out << v.xyz(0) << ' ' << v.xyz(1) << ' ' << v.xyz(2) << ' ' << int(v.rgb(0)) << ' ' << int(v.rgb(1)) << ' '
            << int(v.rgb(2)) << '\n';
    }
  });
}

std::string PlyOptions::Check() const {
  return "";  // switches and a colour: every value is valid
}

}  // namespace pgba
