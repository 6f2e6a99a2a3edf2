#include "pgba/io/gcp_file.h"

#include <iomanip>
#include <map>

#include "pgba/util/atomic_file.h"
#include "pgba/util/error.h"
#include "pgba/util/text_reader.h"

namespace pgba {

std::vector<GcpFileEntry> ReadGcpFile(const std::string& path) {
  TextReader reader(path);
  std::vector<GcpFileEntry> gcps;
  std::map<std::string, size_t> index;
  struct PendingObs {
    std::string gcp;
    GcpFileObservation obs;
  };
  std::vector<PendingObs> pending;
  std::vector<std::string> tok;
  while (reader.NextLine(&tok)) {
    if (tok[0] == "GCP") {
      if (tok.size() != 5 && tok.size() != 6)
        reader.Fail("expected 'GCP name X Y Z [sigma]', got " + std::to_string(tok.size()) + " fields");
      GcpFileEntry g;
      g.name = tok[1];
      g.X = Eigen::Vector3d(reader.ToDouble(tok[2], "X"), reader.ToDouble(tok[3], "Y"), reader.ToDouble(tok[4], "Z"));
      if (tok.size() == 6) {
        g.sigma = reader.ToDouble(tok[5], "sigma");
        if (!(g.sigma > 0)) reader.Fail("sigma must be > 0 (metres), got " + TextReader::Printable(tok[5]));
      }
      g.line = reader.line_number();
      if (!index.emplace(g.name, gcps.size()).second)
        reader.Fail("duplicate GCP '" + TextReader::Printable(g.name) + "' (first on line " +
                    std::to_string(gcps[index.at(g.name)].line) + ")");
      gcps.push_back(g);
    } else if (tok[0] == "OBS") {
      if (tok.size() != 5)
        reader.Fail("expected 'OBS gcp_name image_name x y', got " + std::to_string(tok.size()) + " fields");
      PendingObs p;
      p.gcp = tok[1];
      p.obs.image_name = tok[2];
      p.obs.xy = Eigen::Vector2d(reader.ToDouble(tok[3], "x"), reader.ToDouble(tok[4], "y"));
      p.obs.line = reader.line_number();
      pending.push_back(p);
    } else {
      reader.Fail("unknown record '" + TextReader::Printable(tok[0]) + "' (expected GCP or OBS)");
    }
  }
  if (gcps.empty()) ThrowInputError(path, 0, "no GCP line (expected 'GCP name X Y Z [sigma]')");
  for (const PendingObs& p : pending) {
    const auto it = index.find(p.gcp);
    if (it == index.end())
      ThrowInputError(path, p.obs.line, "OBS names GCP '" + TextReader::Printable(p.gcp) + "' not defined in the file");
    gcps[it->second].observations.push_back(p.obs);
  }
  return gcps;
}

void WriteGcpFile(const std::vector<GcpFileEntry>& gcps, const std::string& path) {
  WriteFileAtomically(path, [&](std::ostream& out) {
    out << std::setprecision(17);
    out << "# GCP name X Y Z [sigma]\n# OBS gcp_name image_name x y\n";
    for (const GcpFileEntry& g : gcps) {
      out << "GCP " << g.name << ' ' << g.X.x() << ' ' << g.X.y() << ' ' << g.X.z();
      if (g.sigma > 0) out << ' ' << g.sigma;
      out << '\n';
      for (const GcpFileObservation& o : g.observations)
        out << "OBS " << g.name << ' ' << o.image_name << ' ' << o.xy.x() << ' ' << o.xy.y() << '\n';
    }
  });
}

}  // namespace pgba
