#include "pgba/io/loop_pairs.h"

#include <cstdio>

#include "pgba/util/atomic_file.h"
#include "pgba/util/error.h"
#include "pgba/util/text_reader.h"

namespace pgba {

namespace {

bool HasWhitespace(const std::string& s) { return s.find_first_of(" \t\r\n") != std::string::npos; }

// %.17g round-trips every double exactly.
std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

}  // namespace

std::vector<LoopCorrespondence> ReadLoopPairs(const std::string& path) {
  std::vector<LoopCorrespondence> pairs;
  TextReader r(path);
  std::vector<std::string> tok;
  while (r.NextLine(&tok)) {
    if (tok.size() != 6)
      r.Fail("expected 6 fields 'name_i x_i y_i name_j x_j y_j', found " + std::to_string(tok.size()));
    LoopCorrespondence c;
    c.name_i = tok[0];
    c.xy_i = Eigen::Vector2d(r.ToDouble(tok[1], "x_i"), r.ToDouble(tok[2], "y_i"));
    c.name_j = tok[3];
    c.xy_j = Eigen::Vector2d(r.ToDouble(tok[4], "x_j"), r.ToDouble(tok[5], "y_j"));
    if (c.name_i == c.name_j)
      r.Fail("a loop correspondence must link two different images, got '" + c.name_i + "' twice");
    pairs.push_back(std::move(c));
  }
  return pairs;
}

void WriteLoopPairs(const std::vector<LoopCorrespondence>& pairs, const std::string& path) {
  for (const auto& c : pairs)
    for (const std::string* name : {&c.name_i, &c.name_j})
      if (name->empty() || HasWhitespace(*name))
        ThrowInputError(path, 0, "image name '" + *name + "' is empty or contains whitespace: not representable");
  WriteFileAtomically(path, [&](std::ostream& out) {
    out << "# Withheld loop correspondences, pixels: name_i x_i y_i name_j x_j y_j\n"
        << "# Number of correspondences: " << pairs.size() << "\n";
    for (const auto& c : pairs)
      out << c.name_i << ' ' << Num(c.xy_i.x()) << ' ' << Num(c.xy_i.y()) << ' ' << c.name_j << ' ' << Num(c.xy_j.x())
          << ' ' << Num(c.xy_j.y()) << '\n';
  });
}

}  // namespace pgba
