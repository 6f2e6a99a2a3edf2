#include "pgba/util/error.h"

namespace pgba {

std::string FormatInputError(const std::string& file, int line, const std::string& problem) {
  std::string s = file;
  if (line > 0) s += ":" + std::to_string(line);
  return s + ": " + problem;
}

void ThrowInputError(const std::string& file, int line, const std::string& problem) {
  throw InputError(FormatInputError(file, line, problem));
}

}  // namespace pgba
