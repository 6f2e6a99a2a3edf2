#!/usr/bin/env bash
# Two builds of pgba timed against each other on the same scenes, in one run: `pgba benchmark`
# runs alternately with build A and build B, REPS times each, and for each build the minimum
# over the runs of the pointless time (adjustment + preparation) and of the point-based time
# is printed with their ratio and the accuracy ratio (median relative rotation error).
# Alternating and taking minima keeps a noisy machine's load out of the comparison.
#
# Usage: bench/ab_time.sh PGBA_A PGBA_B REPS SCENE_DIR...
#   SCENE_DIR: a folder holding scene/input and scene/gt (bench/pose_accuracy.sh OUT leaves
#   one per scene, e.g. OUT/orbit_1).
set -euo pipefail
if [[ $# -lt 4 ]]; then
  echo "usage: $0 PGBA_A PGBA_B REPS SCENE_DIR..." >&2
  exit 2
fi
a=$1 b=$2 reps=$3
shift 3
[[ -x "$a" && -x "$b" ]] || { echo "error: $a or $b is not an executable" >&2; exit 2; }
[[ "$reps" =~ ^[1-9][0-9]*$ ]] || { echo "error: REPS must be a positive integer, got '$reps'" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for scene in "$@"; do
  [[ -d "$scene/scene/input" && -d "$scene/scene/gt" ]] || { echo "error: $scene has no scene/input and scene/gt" >&2; exit 2; }
  : >"$tmp/times"
  for ((r = 1; r <= reps; ++r)); do
    for build in A B; do
      bin=$a
      [[ $build == B ]] && bin=$b
      "$bin" benchmark --tracks "$scene/scene/input" --gt "$scene/scene/gt" --no-convergence --out "$tmp/run" \
        >"$tmp/log" 2>&1 || { echo "error: benchmark failed with $bin on $scene (log: $tmp/log)" >&2; exit 1; }
      python3 - "$tmp/run/benchmark.json" "$build" >>"$tmp/times" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))["methods"]
pl, pb = m["pointless"], m["pointbased"]
print(sys.argv[2], pl["adjust_seconds"] + pl["prepare_seconds"], pb["adjust_seconds"] + pb["prepare_seconds"],
      pl["rel_rot_err_deg_median"] / pb["rel_rot_err_deg_median"])
PY
    done
  done
  python3 - "$tmp/times" "$(basename "$scene")" <<'PY'
import collections, sys
runs = collections.defaultdict(list)
for line in open(sys.argv[1]):
    build, pl, pb, acc = line.split()
    runs[build].append((float(pl), float(pb), float(acc)))
for build in sorted(runs):
    pl = min(r[0] for r in runs[build])
    pb = min(r[1] for r in runs[build])
    print(f"{sys.argv[2]:16} {build}: pointless {pl:.4f} s, point-based {pb:.4f} s, time ratio {pl / pb:.3f}, "
          f"accuracy ratio {runs[build][0][2]:.4f} (min of {len(runs[build])})")
PY
done
