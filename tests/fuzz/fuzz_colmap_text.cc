// Fuzz target: the COLMAP text model (pgba/io/colmap_text.h), its three files given as one
// input separated by "\n=====\n" lines. An accepted model must be consistent and survive a
// write and re-read with the same content.
#include "pgba/io/colmap_text.h"

#include <filesystem>

#include "tests/fuzz/fuzz_support.h"

namespace pgba::fuzz {

std::vector<std::string> Seeds() {
  const std::string cameras =
      "# Camera list\n1 PINHOLE 640 480 500 500 320 240\n2 SIMPLE_RADIAL 800 600 700 400 300 0.01\n"
      "3 OPENCV 640 480 500 510 320 240 -0.05 0.01 0.001 -0.001\n4 RADIAL 640 480 500 320 240 0.02 -0.01\n";
  const std::string images =
      "# Image list\n1 1 0 0 0 0 0 0 1 first image.jpg\n10 20 1 30 40 -1 50 60 2\n"
      "2 0.70710678118654757 0.70710678118654757 0 0 1 2 3 2 second.jpg\n11 21 1 31 41 2\n"
      "3 1 0 0 0 0 0 1 3 third.jpg\n\n";
  const std::string points = "# 3D point list\n1 0.5 0.5 5 255 0 0 0.25 1 0 2 0\n2 1 1 1 0 0 0 -1 1 2 2 1\n";
  return {JoinParts({cameras, images, points}), JoinParts({cameras, images, ""}),
          JoinParts({"1 SIMPLE_PINHOLE 100 100 90 50 50\n", "7 1 0 0 0 0 0 0 1 a\n\n8 1 0 0 0 1 0 0 1 b\n\n", ""})};
}

}  // namespace pgba::fuzz

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  namespace fs = std::filesystem;
  using namespace pgba;
  const std::vector<std::string> parts = fuzz::SplitParts(fuzz::Bytes(data, size), 3);
  const fs::path dir = fuzz::ScratchDir() / "model";
  fs::create_directories(dir);
  fuzz::WriteScratchFile("model/cameras.txt", parts[0]);
  fuzz::WriteScratchFile("model/images.txt", parts[1]);
  // An empty third part stands for a model without points3D.txt (ground-truth models).
  const bool no_points = parts[2].empty();
  if (no_points) fs::remove(dir / "points3D.txt");
  else fuzz::WriteScratchFile("model/points3D.txt", parts[2]);
  fuzz::ExpectValueOrInputError(dir.string(), [&] {
    const Reconstruction rec = ReadColmapText(dir.string(), /*points_optional=*/no_points);
    fuzz::Require(rec.CheckConsistency().empty(), "accepted an inconsistent model: " + rec.CheckConsistency());
    const fs::path copy = fuzz::ScratchDir() / "copy";
    WriteColmapText(rec, copy.string());
    const Reconstruction back = ReadColmapText(copy.string());
    fuzz::Require(back.images.size() == rec.images.size() && back.points3D.size() == rec.points3D.size() &&
                      back.NumObservations() == rec.NumObservations(),
                  "write -> read changed the model");
  });
  return 0;
}
