#!/usr/bin/env bash
# The parser and pipeline-determinism tests under AddressSanitizer + UndefinedBehaviorSanitizer
# (what CI runs after the normal suite), in build-asan/ beside the normal build:
#   - tests of the folders io, util and scene (every parser, atomic outputs, camera models),
#   - every fuzz target's deterministic corpus (tests/fuzz, label "fuzz"),
#   - tests/apps/determinism_cli_test.cc (1 / 2 threads: reconstruct, init with track
#     positioning, run on rendered photos) and the hostile-input CLI tests (hostile_*_cli_test.cc:
#     names, ids, numbers, paths and outputs, caches, messages, from the binary).
# About 20 min of build on 2 cores, then the tests: about 5 min for the parsers and fuzz
# corpora, plus the run, track-positioning and hostile-input suites (1.5 min in Release,
# several times that under ASan). Extra arguments go to cmake.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Release -DPGBA_SANITIZE=ON "$@" > build-asan.log 2>&1 ||
  { cat build-asan.log; exit 1; }
targets=(pgba test_io test_util test_scene test_apps)
for t in tests/fuzz/fuzz_*.cc; do
  name=$(basename "$t" .cc)
  [ "$name" = fuzz_support ] || [ "$name" = fuzz_driver ] || targets+=("$name")
done
cmake --build build-asan -j"$(nproc)" --target "${targets[@]}" 2>&1 | tail -n 3
cd build-asan
# Leaks are reported for the whole process, third-party singletons (TBB, OpenCV) included.
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
ctest --output-on-failure -j"$(nproc)" -L "^(io|util|scene|fuzz)$"
ctest --output-on-failure -R "^(DeterminismCli|Hostile[A-Za-z]*Cli)\."
