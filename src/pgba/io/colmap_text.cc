#include "pgba/io/colmap_text.h"

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "pgba/io/input_checks.h"
#include "pgba/util/atomic_file.h"
#include "pgba/util/error.h"
#include "pgba/util/input_file.h"
#include "pgba/util/text_reader.h"

namespace pgba {
namespace fs = std::filesystem;

namespace {

// %.17g round-trips every double exactly.
std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

uint32_t ToId32(const TextReader& r, const std::string& tok, const char* what) {
  const int64_t v = r.ToInt(tok, what);
  if (v < 0 || v > static_cast<int64_t>(UINT32_MAX)) r.Fail(std::string(what) + " out of range: " + tok);
  return static_cast<uint32_t>(v);
}

Image ParseImageHeader(const TextReader& r, const std::vector<std::string>& tok, const Reconstruction& rec) {
  r.RequireTokens(tok, 10, "image line (IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME)");
  Image im;
  im.image_id = ToId32(r, tok[0], "IMAGE_ID");
  if (rec.images.count(im.image_id)) r.Fail("duplicate IMAGE_ID " + tok[0]);
  const Eigen::Quaterniond q(r.ToDouble(tok[1], "QW"), r.ToDouble(tok[2], "QX"), r.ToDouble(tok[3], "QY"),
                             r.ToDouble(tok[4], "QZ"));
  if (std::abs(q.norm() - 1.0) > 1e-3) r.Fail("quaternion is not unit length (norm " + Num(q.norm()) + ")");
  const Eigen::Vector3d t(r.ToDouble(tok[5], "TX"), r.ToDouble(tok[6], "TY"), r.ToDouble(tok[7], "TZ"));
  im.pose = Pose::FromQt(q, t);
  im.camera_id = ToId32(r, tok[8], "CAMERA_ID");
  if (!rec.cameras.count(im.camera_id)) r.Fail("CAMERA_ID " + tok[8] + " is not in cameras.txt");
  // Names may contain spaces: the rest of the raw line, byte for byte. A name the writer would
  // refuse (a NUL byte) is refused here, so that every model read can be written back.
  im.name = r.RestOfLine(9);
  if (const std::string problem = CheckImageName(im.name); !problem.empty()) r.Fail(problem);
  return im;
}

// Reads images.txt; `points2D_line[image_id]` receives the line of each POINTS2D list so
// that references to points3D.txt can be reported where they are written.
void ReadImages(const std::string& path, Reconstruction* rec, std::map<uint32_t, int>* points2D_line) {
  TextReader r(path);
  std::vector<std::string> tok, pts;
  // Images are matched by name everywhere (ground truth, workspaces, GCPs): two images of
  // one name would let `evaluate --gt` align on the wrong one.
  std::map<std::string, uint32_t> id_of_name;
  while (r.NextLine(&tok)) {
    Image im = ParseImageHeader(r, tok, *rec);
    const auto [named, fresh] = id_of_name.emplace(im.name, im.image_id);
    if (!fresh)
      r.Fail("duplicate image NAME '" + TextReader::Printable(im.name) + "' (IMAGE_ID " +
             std::to_string(named->second) + " has it too)");
    // The POINTS2D line always follows the header and may be empty (no observations);
    // end of file right after the header is read as an empty line too.
    r.NextRawLine(&pts);
    (*points2D_line)[im.image_id] = r.line_number();
    if (pts.size() % 3 != 0) r.Fail("POINTS2D line must hold triples X Y POINT3D_ID");
    im.points2D.resize(pts.size() / 3);
    for (size_t k = 0; k < im.points2D.size(); ++k) {
      im.points2D[k].xy = Eigen::Vector2d(r.ToDouble(pts[3 * k], "X"), r.ToDouble(pts[3 * k + 1], "Y"));
      const int64_t pid = r.ToInt(pts[3 * k + 2], "POINT3D_ID");
      if (pid < -1) r.Fail("POINT3D_ID must be -1 or non-negative");
      im.points2D[k].point3D_id = pid;
    }
    rec->images[im.image_id] = std::move(im);
  }
}

// Reads points3D.txt. Every track element must resolve to an observation of images.txt that
// is linked back to this point; `listed` marks the observations some track lists.
void ReadPoints(const std::string& path, Reconstruction* rec, std::map<uint32_t, std::vector<bool>>* listed) {
  for (const auto& [id, im] : rec->images) (*listed)[id].assign(im.points2D.size(), false);
  TextReader r(path);
  std::vector<std::string> tok;
  while (r.NextLine(&tok)) {
    r.RequireTokens(tok, 8, "point line (POINT3D_ID X Y Z R G B ERROR TRACK[])");
    Point3D p;
    const int64_t pid = r.ToInt(tok[0], "POINT3D_ID");
    if (pid < 0) r.Fail("negative POINT3D_ID");
    p.point3D_id = static_cast<uint64_t>(pid);
    if (rec->points3D.count(p.point3D_id)) r.Fail("duplicate POINT3D_ID " + tok[0]);
    p.xyz = Eigen::Vector3d(r.ToDouble(tok[1], "X"), r.ToDouble(tok[2], "Y"), r.ToDouble(tok[3], "Z"));
    for (int c = 0; c < 3; ++c) {
      const int64_t v = r.ToInt(tok[4 + c], "color");
      if (v < 0 || v > 255) r.Fail("color out of range 0..255");
      p.color(c) = static_cast<uint8_t>(v);
    }
    p.error = r.ToDouble(tok[7], "ERROR");
    if ((tok.size() - 8) % 2 != 0) r.Fail("TRACK must hold pairs IMAGE_ID POINT2D_IDX");
    for (size_t k = 8; k + 1 < tok.size(); k += 2) {
      TrackElement e;
      e.image_id = ToId32(r, tok[k], "IMAGE_ID");
      e.point2D_idx = ToId32(r, tok[k + 1], "POINT2D_IDX");
      auto im = rec->images.find(e.image_id);
      if (im == rec->images.end()) r.Fail("track refers to IMAGE_ID " + tok[k] + " not in images.txt");
      if (e.point2D_idx >= im->second.points2D.size())
        r.Fail("track refers to POINT2D_IDX " + tok[k + 1] + " beyond the " +
               std::to_string(im->second.points2D.size()) + " observations of image " + tok[k]);
      if (im->second.points2D[e.point2D_idx].point3D_id != pid)
        r.Fail("track element (" + tok[k] + ", " + tok[k + 1] + ") is not linked to this point in images.txt");
      auto flag = (*listed)[e.image_id].begin() + e.point2D_idx;
      if (*flag) r.Fail("track lists element (" + tok[k] + ", " + tok[k + 1] + ") twice");
      *flag = true;
      p.track.push_back(e);
    }
    rec->points3D[p.point3D_id] = std::move(p);
  }
}

}  // namespace

namespace {
constexpr const char* kNoPriorFocalMarker = "# pgba: no prior focal length:";

// The ids of the marker comment (see the header), each checked against `cams`.
void ReadNoPriorFocalMarker(const std::string& path, std::map<uint32_t, Camera>* cams) {
  std::ifstream in(path);
  std::string line;
  const std::string marker = kNoPriorFocalMarker;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.compare(0, marker.size(), marker) != 0) continue;
    std::istringstream ids(line.substr(marker.size()));
    std::string token;
    while (ids >> token) {
      const bool digits = !token.empty() && token.size() <= 10 &&
                          std::all_of(token.begin(), token.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
      const unsigned long long id = digits ? std::stoull(token) : 0ull;
      const auto it = digits && id <= 0xffffffffull ? cams->find(static_cast<uint32_t>(id)) : cams->end();
      if (it == cams->end())
        ThrowInputError(path, number, "'" + TextReader::Printable(token) + "' of \"" + marker +
                                          "\" is not a CAMERA_ID of this file");
      it->second.has_prior_focal_length = false;
    }
  }
}
}  // namespace

std::map<uint32_t, Camera> ReadColmapCameras(const std::string& path) {
  std::map<uint32_t, Camera> cams;
  TextReader r(path);
  std::vector<std::string> tok;
  while (r.NextLine(&tok)) {
    r.RequireTokens(tok, 4, "camera line (CAMERA_ID MODEL WIDTH HEIGHT PARAMS[])");
    Camera c;
    c.camera_id = ToId32(r, tok[0], "CAMERA_ID");
    if (cams.count(c.camera_id)) r.Fail("duplicate CAMERA_ID " + tok[0]);
    if (!ParseCameraModel(tok[1], &c.model))
      r.Fail("unknown or unsupported camera model '" + TextReader::Printable(tok[1]) +
             "' (supported: SIMPLE_PINHOLE PINHOLE SIMPLE_RADIAL RADIAL OPENCV)");
    const int64_t w = r.ToInt(tok[2], "WIDTH"), h = r.ToInt(tok[3], "HEIGHT");
    if (w <= 0 || h <= 0 || w > 1000000 || h > 1000000) r.Fail("image size out of range");
    c.width = static_cast<int>(w);
    c.height = static_cast<int>(h);
    for (size_t k = 4; k < tok.size(); ++k) c.params.push_back(r.ToDouble(tok[k], "camera parameter"));
    const std::string problem = CheckCamera(c);
    if (!problem.empty()) r.Fail(problem);
    cams[c.camera_id] = std::move(c);
  }
  ReadNoPriorFocalMarker(path, &cams);
  return cams;
}

Reconstruction ReadColmapText(const std::string& dir, bool points_optional) {
  RequireDirectory(dir, "model directory", "a COLMAP text model");
  Reconstruction rec;
  rec.cameras = ReadColmapCameras((fs::path(dir) / "cameras.txt").string());
  const std::string images_path = (fs::path(dir) / "images.txt").string();
  std::map<uint32_t, int> points2D_line;
  ReadImages(images_path, &rec, &points2D_line);
  std::error_code ec;
  const std::string points_path = (fs::path(dir) / "points3D.txt").string();
  if (points_optional && fs::status(points_path, ec).type() == fs::file_type::not_found) {
    for (auto& [id, im] : rec.images)
      for (auto& p : im.points2D) p.point3D_id = kNoPoint3D;
    return rec;
  }
  std::map<uint32_t, std::vector<bool>> listed;
  ReadPoints(points_path, &rec, &listed);
  // The other direction: every observation linked to a point must be in that point's track.
  for (const auto& [id, im] : rec.images) {
    for (size_t k = 0; k < im.points2D.size(); ++k) {
      const int64_t pid = im.points2D[k].point3D_id;
      if (pid == kNoPoint3D || listed[id][k]) continue;
      const std::string what = "observation " + std::to_string(k) + " of IMAGE_ID " + std::to_string(id);
      if (!rec.points3D.count(static_cast<uint64_t>(pid)))
        ThrowInputError(images_path, points2D_line[id],
                        what + " refers to POINT3D_ID " + std::to_string(pid) + " not in points3D.txt");
      ThrowInputError(images_path, points2D_line[id],
                      what + " is linked to POINT3D_ID " + std::to_string(pid) +
                          " but that point's track in points3D.txt does not list it");
    }
  }
  const std::string problem = rec.CheckConsistency();  // safety net: all checked above
  if (!problem.empty()) ThrowInputError(dir, 0, "inconsistent model: " + problem);
  return rec;
}

void WriteColmapCamerasFile(const Reconstruction& rec, const std::string& path) {
  WriteFileAtomically(path, [&](std::ostream& out) {
    out << "# Camera list with one line of data per camera:\n"
        << "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
        << "# Number of cameras: " << rec.cameras.size() << "\n";
    std::string no_prior;
    for (const auto& [id, c] : rec.cameras)
      if (!c.has_prior_focal_length) no_prior += " " + std::to_string(id);
    if (!no_prior.empty()) out << kNoPriorFocalMarker << no_prior << "\n";
    for (const auto& [id, c] : rec.cameras) {
      out << id << ' ' << CameraModelName(c.model) << ' ' << c.width << ' ' << c.height;
      for (double p : c.params) out << ' ' << Num(p);
      out << '\n';
    }
  });
}

namespace {
// A name the images.txt line would not give back as it is (a line break, whitespace at an
// end) is refused before anything is written: `where` names the output.
void RequireWritableNames(const Reconstruction& rec, const std::string& where) {
  for (const auto& [id, im] : rec.images)
    if (const std::string problem = CheckImageName(im.name); !problem.empty())
      ThrowInputError(where, 0, "image " + std::to_string(id) + ": " + problem);
}
}  // namespace

void WriteColmapImagesFile(const Reconstruction& rec, const std::string& path) {
  RequireWritableNames(rec, path);
  WriteFileAtomically(path, [&](std::ostream& out) {
    out << "# Image list with two lines of data per image:\n"
        << "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
        << "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
        << "# Number of images: " << rec.images.size() << ", observations: " << rec.NumObservations() << "\n";
    for (const auto& [id, im] : rec.images) {
      const auto& q = im.pose.q();
      const auto& t = im.pose.t();
      out << id << ' ' << Num(q.w()) << ' ' << Num(q.x()) << ' ' << Num(q.y()) << ' ' << Num(q.z()) << ' '
          << Num(t.x()) << ' ' << Num(t.y()) << ' ' << Num(t.z()) << ' ' << im.camera_id << ' ' << im.name << '\n';
      bool first = true;
      for (const auto& p : im.points2D) {
        if (!first) out << ' ';
        first = false;
        out << Num(p.xy.x()) << ' ' << Num(p.xy.y()) << ' ' << p.point3D_id;
      }
      out << '\n';
    }
  });
}

void WriteColmapPointsFile(const Reconstruction& rec, const std::string& path) {
  WriteFileAtomically(path, [&](std::ostream& out) {
    out << "# 3D point list with one line of data per point:\n"
        << "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
        << "# Number of points: " << rec.points3D.size() << "\n";
    for (const auto& [id, p] : rec.points3D) {
      out << id << ' ' << Num(p.xyz.x()) << ' ' << Num(p.xyz.y()) << ' ' << Num(p.xyz.z()) << ' '
          << int(p.color(0)) << ' ' << int(p.color(1)) << ' ' << int(p.color(2)) << ' ' << Num(p.error);
      for (const auto& e : p.track) out << ' ' << e.image_id << ' ' << e.point2D_idx;
      out << '\n';
    }
  });
}

void WriteColmapText(const Reconstruction& rec, const std::string& dir) {
  RequireWritableNames(rec, dir);
  StagedDirectory staged(dir);
  WriteColmapCamerasFile(rec, (staged.path() / "cameras.txt").string());
  WriteColmapImagesFile(rec, (staged.path() / "images.txt").string());
  WriteColmapPointsFile(rec, (staged.path() / "points3D.txt").string());
  staged.Commit();
}

}  // namespace pgba
