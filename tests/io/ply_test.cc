// PLY export: header, counts and every vertex read back, binary and ASCII.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "pgba/geometry/rotation.h"
#include "pgba/io/ply.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

struct PlyVertex {
  Eigen::Vector3d xyz;
  int rgb[3];
};

struct PlyFile {
  std::vector<std::string> header;
  std::vector<PlyVertex> vertices;
  size_t trailing_bytes = 0;
};

// An independent minimal reader of what WritePly promises (double xyz, uchar rgb).
PlyFile ReadPly(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  PlyFile f;
  std::string line;
  size_t count = 0;
  bool binary = false;
  while (std::getline(in, line)) {
    f.header.push_back(line);
    if (line.rfind("element vertex ", 0) == 0) count = std::stoul(line.substr(15));
    if (line == "format binary_little_endian 1.0") binary = true;
    if (line == "end_header") break;
  }
  for (size_t i = 0; i < count; ++i) {
    PlyVertex v;
    if (binary) {
      char buf[27];
      in.read(buf, 27);
      for (int k = 0; k < 3; ++k) std::memcpy(&v.xyz(k), buf + 8 * k, 8);  // little-endian host
      for (int k = 0; k < 3; ++k) v.rgb[k] = static_cast<unsigned char>(buf[24 + k]);
    } else {
      in >> v.xyz(0) >> v.xyz(1) >> v.xyz(2) >> v.rgb[0] >> v.rgb[1] >> v.rgb[2];
    }
    if (!in) break;
    f.vertices.push_back(v);
  }
  if (!binary) in >> std::ws;
  std::string rest((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  f.trailing_bytes = rest.size();
  return f;
}

Reconstruction SmallScene() {
  Reconstruction rec;
  Camera cam;
  cam.camera_id = 1;
  cam.params = {500, 500, 320, 240};
  cam.width = 640;
  cam.height = 480;
  rec.cameras[1] = cam;
  for (uint32_t i = 1; i <= 2; ++i) {
    Image im;
    im.image_id = i;
    im.name = "im" + std::to_string(i);
    im.camera_id = 1;
    im.pose = Pose::FromRC(ExpSO3(Eigen::Vector3d(0.1 * i, 0.2, -0.3)), Eigen::Vector3d(0.1 * i, -2.0, 1e6 + 0.125 * i));
    rec.images[i] = im;
  }
  const Eigen::Vector3d pts[3] = {{1.0, 2.0, 3.0}, {-0.1, 1e-7, 123456.789}, {4.0, 5.0, 6.0}};
  for (int k = 0; k < 3; ++k) {
    Point3D& p = rec.points3D[10 + k];
    p.point3D_id = 10 + k;
    p.xyz = pts[k];
    p.color = Eigen::Matrix<uint8_t, 3, 1>(10 * k, 255 - k, 7);
  }
  return rec;
}

TEST(Ply, BinaryAndAsciiRoundTrip) {
  const fs::path dir = fs::temp_directory_path() / ("pgba_ply_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const Reconstruction rec = SmallScene();
  for (bool binary : {true, false}) {
    PlyOptions opt;
    opt.binary = binary;
    const fs::path path = dir / (binary ? "bin.ply" : "ascii.ply");
    WritePly(rec, path.string(), opt);
    const PlyFile f = ReadPly(path);
    ASSERT_GE(f.header.size(), 4u);
    EXPECT_EQ(f.header[0], "ply");
    EXPECT_EQ(f.header[1], binary ? "format binary_little_endian 1.0" : "format ascii 1.0");
    EXPECT_NE(std::find(f.header.begin(), f.header.end(), "element vertex 5"), f.header.end());
    EXPECT_NE(std::find(f.header.begin(), f.header.end(), "comment pgba points 3 cameras 2"), f.header.end());
    EXPECT_EQ(f.header.back(), "end_header");
    ASSERT_EQ(f.vertices.size(), 5u);
    EXPECT_EQ(f.trailing_bytes, 0u);
    size_t k = 0;
    for (const auto& [id, p] : rec.points3D) {
      EXPECT_EQ(f.vertices[k].xyz, p.xyz) << k;  // exact: doubles, 17 digits in ASCII
      for (int c = 0; c < 3; ++c) EXPECT_EQ(f.vertices[k].rgb[c], p.color(c));
      ++k;
    }
    for (const auto& [id, im] : rec.images) {
      EXPECT_EQ(f.vertices[k].xyz, im.pose.C());
      EXPECT_EQ(f.vertices[k].rgb[0], 255);
      EXPECT_EQ(f.vertices[k].rgb[1], 0);
      EXPECT_EQ(f.vertices[k].rgb[2], 255);
      ++k;
    }
  }
  PlyOptions no_cams;
  no_cams.camera_centers = false;
  WritePly(rec, (dir / "bin.ply").string(), no_cams);  // overwrites
  EXPECT_EQ(ReadPly(dir / "bin.ply").vertices.size(), 3u);
  // Only the two outputs: no temporaries left behind.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 2);
  fs::remove_all(dir);
}

TEST(Ply, UnwritablePathThrowsAndLeavesNothing) {
  const fs::path dir = fs::temp_directory_path() / ("pgba_ply_bad_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "a_file") << "x";
  EXPECT_ANY_THROW(WritePly(SmallScene(), (dir / "a_file" / "out.ply").string()));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pgba
