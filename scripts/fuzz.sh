#!/usr/bin/env bash
# Open-ended fuzzing of one parser with libFuzzer (clang, ASan + UBSan), for longer runs than
# the few seconds of deterministic mutations that ctest gives each target:
#   bash scripts/fuzz.sh colmap_text 600        # target, seconds (default 300)
# Targets: the tests/fuzz/fuzz_<target>.cc files (colmap_text colmap_database json_config
# gcp_file loop_pairs feature_file workspace_json). The corpus starts from the target's
# checked-in corpus (tests/fuzz/corpus/<target>/) and grows in build-fuzz/corpus/<target>/
# (an input worth keeping, such as a crash once fixed, goes into the checked-in one); crashes are written to build-fuzz/crash-* (replay
# one: build-fuzz/bin/libfuzz_<target> build-fuzz/crash-...). Every library is built with
# clang's ASan + UBSan and coverage instrumentation: the first build of a target of the core
# library takes about 20 min on 2 shared cores, json_config (every module) 30 min more.
set -euo pipefail
cd "$(dirname "$0")/.."
target=${1:?usage: scripts/fuzz.sh TARGET [SECONDS]}
seconds=${2:-300}
bash scripts/install_deps.sh
dpkg-query -W -f='${Status}\n' clang libclang-rt-14-dev 2>/dev/null | grep -c "install ok installed" | grep -q 2 ||
  { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends clang libclang-rt-14-dev; }
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DPGBA_SANITIZE=ON -DPGBA_LIBFUZZER=ON > build-fuzz.log 2>&1 || { cat build-fuzz.log; exit 1; }
cmake --build build-fuzz -j"$(nproc)" --target "fuzz_$target" "libfuzz_$target" 2>&1 | tail -n 3
cd build-fuzz
mkdir -p "corpus/$target"
cp -n ../tests/fuzz/corpus/"$target"/* "corpus/$target/"
export ASAN_OPTIONS="detect_leaks=0"  # third-party singletons (TBB, OpenCV) hold memory at exit
export UBSAN_OPTIONS="print_stacktrace=1"
"./bin/libfuzz_$target" -max_total_time="$seconds" -timeout=10 "corpus/$target"
