#include "pgba/util/checksum.h"

#include <cstdio>

namespace pgba {

std::string Hex64(uint64_t value) {
  char buf[17];
  std::snprintf(buf, sizeof(buf), "%016llx", static_cast<unsigned long long>(value));
  return buf;
}

}  // namespace pgba
