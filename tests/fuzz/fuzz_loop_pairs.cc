// Fuzz target: the withheld loop correspondences (pgba/io/loop_pairs.h). An accepted file
// must survive a write and re-read bit for bit.
#include "pgba/io/loop_pairs.h"

#include "tests/fuzz/fuzz_support.h"

namespace pgba::fuzz {

std::vector<std::string> Seeds() {
  return {"# loop\na.jpg 10.5 20.25 b.jpg 30 40\nc.jpg 1e-3 -2 d.jpg 0.1 0.2\n", "x 1 2 y 3 4", ""};
}

}  // namespace pgba::fuzz

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pgba;
  const std::string path = fuzz::WriteScratchFile("loop_pairs.txt", fuzz::Bytes(data, size));
  fuzz::ExpectValueOrInputError(path, [&] {
    const std::vector<LoopCorrespondence> pairs = ReadLoopPairs(path);
    const std::string copy = (fuzz::ScratchDir() / "loop_copy.txt").string();
    WriteLoopPairs(pairs, copy);
    const std::vector<LoopCorrespondence> back = ReadLoopPairs(copy);
    fuzz::Require(back.size() == pairs.size(), "write -> read changed the count");
    for (size_t k = 0; k < pairs.size(); ++k)
      fuzz::Require(back[k].name_i == pairs[k].name_i && back[k].xy_i == pairs[k].xy_i &&
                        back[k].name_j == pairs[k].name_j && back[k].xy_j == pairs[k].xy_j,
                    "write -> read changed correspondence " + std::to_string(k));
  });
  return 0;
}
