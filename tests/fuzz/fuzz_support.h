// Shared by the fuzz targets (one per parser, tests/fuzz/fuzz_<parser>.cc). A target defines
//   extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);  // libFuzzer's entry
//   std::vector<std::string> pgba::fuzz::Seeds();  // its deterministic seed corpus, built in code
// and is linked either with fuzz_driver.cc (ctest: the seeds and a fixed number of seeded
// mutations of them) or with libFuzzer (-DPGBA_LIBFUZZER=ON, scripts/fuzz.sh).
//
// The contract a parser must keep, whatever the bytes: return a value or throw InputError
// (with a one-line message naming the file). Any other exception aborts, so the driver and
// libFuzzer report it like a crash.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace pgba::fuzz {

std::vector<std::string> Seeds();

// A scratch directory of this process (in /dev/shm when there is one: no disk writes per
// input), created on first use and removed at exit.
const std::filesystem::path& ScratchDir();

// Writes `bytes` to ScratchDir()/name and returns the path.
std::string WriteScratchFile(const std::string& name, const std::string& bytes);

inline std::string Bytes(const uint8_t* data, size_t size) { return std::string(reinterpret_cast<const char*>(data), size); }

// Runs `parse`; InputError is the expected outcome for bad input (its message must be one
// line starting with `path`); anything else aborts with the exception's message.
void ExpectValueOrInputError(const std::string& path, const std::function<void()>& parse);

// Aborts with `what` unless `ok`: for the checks a target makes on an accepted value.
void Require(bool ok, const std::string& what);

// Splits `bytes` at the separator lines "\n=====\n" into exactly `n` parts (missing parts are
// empty): multi-file inputs (a COLMAP model's three files) as one fuzz input.
std::vector<std::string> SplitParts(const std::string& bytes, size_t n);
std::string JoinParts(const std::vector<std::string>& parts);

}  // namespace pgba::fuzz
