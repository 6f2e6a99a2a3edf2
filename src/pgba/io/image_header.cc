#include "pgba/io/image_header.h"

#include <algorithm>
#include <cstdint>
#include <fstream>

#include "pgba/util/error.h"
#include "pgba/util/input_file.h"

namespace pgba {

namespace {

constexpr int64_t kMaxSide = 1000000;  // as cameras.txt's WIDTH and HEIGHT

std::pair<int, int> Checked(const std::string& path, int64_t width, int64_t height) {
  if (width < 1 || height < 1 || width > kMaxSide || height > kMaxSide)
    ThrowInputError(path, 0,
                    "image header declares a size of " + std::to_string(width) + "x" + std::to_string(height) +
                        " pixels (corrupt file?)");
  return {static_cast<int>(width), static_cast<int>(height)};
}

uint32_t Be(const unsigned char* p, int bytes) {
  uint32_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | p[i];
  return v;
}

// Walks the JPEG markers up to the first start-of-frame (SOFn: C0..CF except C4 DHT, C8 JPG,
// CC DAC), whose payload is precision, height, width.
std::pair<int, int> JpegSize(const std::string& path, std::ifstream& in) {
  in.seekg(2);
  unsigned char b[8];
  for (;;) {
    int c = in.get();
    if (c == EOF) break;
    if (c != 0xFF) ThrowInputError(path, 0, "JPEG marker expected before the frame header (corrupt file?)");
    int marker;
    do marker = in.get();
    while (marker == 0xFF);
    if (marker == EOF) break;
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) continue;  // no payload
    if (marker == 0xD9 || marker == 0xDA) break;                          // end of image, start of scan
    if (!in.read(reinterpret_cast<char*>(b), 2)) break;
    const uint32_t length = Be(b, 2);
    if (length < 2) ThrowInputError(path, 0, "JPEG segment of length " + std::to_string(length) + " (corrupt file?)");
    if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC) {
      if (!in.read(reinterpret_cast<char*>(b), 5)) break;
      return Checked(path, Be(b + 3, 2), Be(b + 1, 2));
    }
    in.seekg(length - 2, std::ios::cur);
  }
  ThrowInputError(path, 0, "JPEG without a frame header before its image data (truncated or corrupt file)");
}

}  // namespace

std::pair<int, int> ReadImageSize(const std::string& path) {
  RequireRegularFile(path);
  std::ifstream in(path, std::ios::binary);
  unsigned char h[24] = {};
  in.read(reinterpret_cast<char*>(h), 24);
  const std::streamsize got = in.gcount();
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (got >= 8 && std::equal(kPng, kPng + 8, h)) {
    if (got < 24 || std::string(reinterpret_cast<char*>(h + 12), 4) != "IHDR")
      ThrowInputError(path, 0, "PNG without its IHDR header (truncated or corrupt file)");
    return Checked(path, Be(h + 16, 4), Be(h + 20, 4));
  }
  if (got >= 3 && h[0] == 0xFF && h[1] == 0xD8 && h[2] == 0xFF) {
    in.clear();
    return JpegSize(path, in);
  }
  ThrowInputError(path, 0, "not a PNG or JPEG photo");
}

}  // namespace pgba
