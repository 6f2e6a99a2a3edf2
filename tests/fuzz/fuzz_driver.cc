// The ctest driver of a fuzz target: runs every seed of pgba::fuzz::Seeds() and every file of
// the target's checked-in corpus (`--corpus DIR`: tests/fuzz/corpus/<target>/, the seeds
// and the inputs that once crashed a parser), then `--iterations` mutations of them drawn from
// a fixed-seed generator, so that a run is reproducible (a failure names its iteration;
// `--only N` replays it) and takes a few seconds. `--dump-seeds DIR` writes the seeds as
// files (how the corpus was made).
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

// Values that parsers tend to mishandle: limits, wrap-around, non-finite numbers, JSON and
// line structure.
const char* const kTokens[] = {"0",  "-1", "-0", "1e999", "-1e999", "nan", "inf", "1e-320", "4294967296",
                               "4611686018427387904", "18446744073709551616", "9223372036854775807",
                               "0.5", "\n", "\r\n", " ", "\t", "#", "\"", "{", "}", "[", "]", ",", ":", "null",
                               "true", "1.0", "\"\"", "{}", "[]", "PINHOLE", "OPENCV", "GCP", "OBS", "END."};

std::string Mutate(std::mt19937_64& rng, const std::vector<std::string>& seeds, std::string s) {
  const int ops = 1 + static_cast<int>(rng() % 4);
  for (int op = 0; op < ops; ++op) {
    const size_t n = s.size();
    const size_t at = n ? rng() % n : 0;
    switch (rng() % 8) {
      case 0:  // flip a bit
        if (n) s[at] = static_cast<char>(s[at] ^ (1 << (rng() % 8)));
        break;
      case 1: {  // set a byte to an interesting value
        const unsigned char values[] = {0x00, 0x01, 0x7f, 0x80, 0xff, '\n', ' ', '9'};
        if (n) s[at] = static_cast<char>(values[rng() % sizeof(values)]);
        break;
      }
      case 2:  // truncate
        s.resize(at);
        break;
      case 3:  // insert a token
        s.insert(at, kTokens[rng() % (sizeof(kTokens) / sizeof(kTokens[0]))]);
        break;
      case 4: {  // replace a number-ish run of characters by a token
        size_t end = at;
        while (end < n && (std::isalnum(static_cast<unsigned char>(s[end])) || s[end] == '.' || s[end] == '-')) ++end;
        s.replace(at, end - at, kTokens[rng() % (sizeof(kTokens) / sizeof(kTokens[0]))]);
        break;
      }
      case 5:  // delete a chunk
        if (n) s.erase(at, 1 + rng() % std::min<size_t>(n - at, 64));
        break;
      case 6:  // duplicate a chunk
        if (n) s.insert(at, s.substr(at, 1 + rng() % std::min<size_t>(n - at, 64)));
        break;
      default: {  // splice with another seed
        const std::string& other = seeds[rng() % seeds.size()];
        if (!other.empty()) s = s.substr(0, at) + other.substr(rng() % other.size());
      }
    }
  }
  return s;
}

void Run(const std::string& input) {
  LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(input.data()), input.size());
}

}  // namespace

int main(int argc, char** argv) {
  long iterations = 2000;
  long only = -1;
  std::string dump, corpus;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--iterations") iterations = std::atol(argv[i + 1]);
    else if (flag == "--only") only = std::atol(argv[i + 1]);
    else if (flag == "--dump-seeds") dump = argv[i + 1];
    else if (flag == "--corpus") corpus = argv[i + 1];
    else {
      std::fprintf(stderr, "usage: %s [--iterations N] [--only N] [--dump-seeds DIR] [--corpus DIR]\n", argv[0]);
      return 2;
    }
  }
  std::vector<std::string> seeds = pgba::fuzz::Seeds();
  if (!corpus.empty()) {
    // Every file of the corpus, in name order (a deterministic run); a missing or empty
    // corpus is a failure, not a run over nothing.
    std::vector<std::filesystem::path> files;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(corpus, ec))
      if (e.is_regular_file()) files.push_back(e.path());
    if (ec || files.empty()) {
      std::fprintf(stderr, "%s: no corpus file in %s\n", argv[0], corpus.c_str());
      return 1;
    }
    std::sort(files.begin(), files.end());
    for (const std::filesystem::path& f : files) {
      std::ifstream in(f, std::ios::binary);
      seeds.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    std::printf("%s: %zu corpus files from %s\n", argv[0], files.size(), corpus.c_str());
  }
  if (seeds.empty()) {
    std::fprintf(stderr, "no seeds\n");
    return 1;
  }
  if (!dump.empty()) {
    std::filesystem::create_directories(dump);
    for (size_t k = 0; k < seeds.size(); ++k)
      std::ofstream(std::filesystem::path(dump) / ("seed_" + std::to_string(k)), std::ios::binary) << seeds[k];
    std::printf("wrote %zu seeds to %s\n", seeds.size(), dump.c_str());
    return 0;
  }
  const auto t0 = std::chrono::steady_clock::now();
  for (const std::string& s : seeds) Run(s);
  std::mt19937_64 rng(20261201);
  for (long it = 0; it < iterations; ++it) {
    const std::string input = Mutate(rng, seeds, seeds[rng() % seeds.size()]);
    if (only >= 0 && it != only) continue;
    if (only >= 0 || std::getenv("PGBA_FUZZ_VERBOSE")) std::fprintf(stderr, "iteration %ld: %zu bytes\n", it, input.size());
    Run(input);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%s: %zu seeds + %ld mutations, no crash, %.1f s\n", argv[0], seeds.size(), iterations, seconds);
  return 0;
}
