// Fuzz target: the ground control point file (pgba/io/gcp_file.h). An accepted file must
// survive a write and re-read with the same records.
#include "pgba/io/gcp_file.h"

#include "tests/fuzz/fuzz_support.h"

namespace pgba::fuzz {

std::vector<std::string> Seeds() {
  return {"# GCPs\nGCP g1 10 20 30 0.05\nGCP g2 -1.5 2.25 1e3\nOBS g1 im1.jpg 100.5 200.25\nOBS g2 im2.jpg 5 6\n",
          "OBS late im1.jpg 1 2\nGCP late 0 0 0\n", "GCP only 1 2 3\n",
          "\r\r\nGCP g 1 2 3\n"};  // libFuzzer's find: a line of whitespace only, returned with no token
}

}  // namespace pgba::fuzz

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pgba;
  const std::string path = fuzz::WriteScratchFile("gcp.txt", fuzz::Bytes(data, size));
  fuzz::ExpectValueOrInputError(path, [&] {
    const std::vector<GcpFileEntry> gcps = ReadGcpFile(path);
    const std::string copy = (fuzz::ScratchDir() / "gcp_copy.txt").string();
    WriteGcpFile(gcps, copy);
    const std::vector<GcpFileEntry> back = ReadGcpFile(copy);
    fuzz::Require(back.size() == gcps.size(), "write -> read changed the GCP count");
    for (size_t k = 0; k < gcps.size(); ++k)
      fuzz::Require(back[k].name == gcps[k].name && back[k].X == gcps[k].X &&
                        back[k].observations.size() == gcps[k].observations.size(),
                    "write -> read changed GCP " + gcps[k].name);
  });
  return 0;
}
