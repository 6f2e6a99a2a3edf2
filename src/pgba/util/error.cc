#include "pgba/util/error.h"

#include <cstdio>

namespace pgba {

std::string FormatInputError(const std::string& file, int line, const std::string& problem) {
  std::string s = file;
  if (line > 0) s += ":" + std::to_string(line);
  return s + ": " + problem;
}

void ThrowInputError(const std::string& file, int line, const std::string& problem) {
  throw InputError(FormatInputError(file, line, problem), file.empty() ? std::string("?") : file);
}

std::string OneLine(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (unsigned char c : text) {
    if (c >= 0x20 && c != 0x7f) {
      out += static_cast<char>(c);
    } else {
      char buf[8];
      std::snprintf(buf, sizeof(buf), "\\x%02x", c);
      out += buf;
    }
  }
  return out;
}

}  // namespace pgba
