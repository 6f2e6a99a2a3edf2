// The pixel size of a PNG or JPEG photo from its header, without decoding it: what the
// dataset converters check each camera's size against.
#pragma once

#include <string>
#include <utility>

namespace pgba {

// (width, height). InputError naming the file if it is not a PNG or JPEG, is truncated
// before its size, or declares a size outside 1..1000000 pixels.
std::pair<int, int> ReadImageSize(const std::string& path);

}  // namespace pgba
