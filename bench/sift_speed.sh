#!/usr/bin/env bash
# Feature extraction speed of two builds (or two configs) in one run: `pgba features` on the
# same images, alternately with A and B, REPS times each (fresh workspace, no cache), and for
# each the minimum and the median wall time of the stage (report.json stages.features.seconds:
# decoding + SIFT + writing the feature files, images in parallel on every core), printed as
# seconds per image and per megapixel with the ratio B/A. Alternating and taking minima keeps
# a shared machine's load changes out of the ratio.
# CPU time: the stage's user + system time (report.json stages.features.cpu_seconds, every
# thread) per image, which the other users' load stretches far less than the wall time. The
# target, <= 1 s per 6 MP image on 2 cores, is <= 2 s of CPU time per image when both
# cores work on it (the column "2-core s/image" = CPU / 2, the wall time of a dedicated
# 2-core machine if the work parallelises fully; the measured wall time bounds it above).
#
# Usage: bench/sift_speed.sh PGBA_A PGBA_B REPS DATASET_DIR [N_IMAGES]
#   ARGS_A / ARGS_B: extra arguments of `pgba features` for A and B (e.g.
#   "--sift-implementation opencv"; default: none).
#   N_IMAGES: use only the first N images of DATASET_DIR/images (default: all).
set -euo pipefail
if [[ $# -lt 4 ]]; then echo "usage: $0 PGBA_A PGBA_B REPS DATASET_DIR [N_IMAGES]" >&2; exit 2; fi
a=$1 b=$2 reps=$3 ds=$4 nimg=${5:-0}
[[ -x "$a" && -x "$b" ]] || { echo "error: $a or $b is not an executable" >&2; exit 2; }
[[ -d "$ds/images" && -f "$ds/cameras.txt" ]] || { echo "error: $ds needs images/ and cameras.txt" >&2; exit 2; }
tmp=$(mktemp -d /tmp/pgba_sift_speed_XXXX)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/images"
i=0
for f in $(ls "$ds/images"); do
  if [[ $nimg -gt 0 && $i -ge $nimg ]]; then break; fi
  ln -s "$ds/images/$f" "$tmp/images/$f"
  i=$((i + 1))
done
: >"$tmp/times"
for ((r = 1; r <= reps; ++r)); do
  for build in A B; do
    bin=$a extra=${ARGS_A:-}
    [[ $build == B ]] && bin=$b extra=${ARGS_B:-}
    rm -rf "$tmp/ws"
    "$bin" -v 0 features --images "$tmp/images" --calib "$ds/cameras.txt" --out "$tmp/ws" $extra \
      >"$tmp/log" 2>&1 || { echo "error: features failed with $bin (log below)" >&2; cat "$tmp/log" >&2; exit 1; }
    python3 - "$tmp/ws/report.json" "$build" >>"$tmp/times" <<'PY'
import json, sys
f = json.load(open(sys.argv[1]))["stages"]["features"]
print(sys.argv[2], f["seconds"] if "seconds" in f else f["seconds_per_megapixel"] * f["megapixels_extracted"],
      f["images_extracted"], f["megapixels_extracted"], f.get("features_mean", 0), f.get("cpu_seconds", float("nan")),
      f.get("load_average", float("nan")))
PY
  done
done
python3 - "$tmp/times" "$(basename "$ds")" "$(nproc)" "$a" "$b" <<'PY'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1])]
name, cores = sys.argv[2], sys.argv[3]
print(f"{name}: features on {cores} cores, A = {sys.argv[4]}, B = {sys.argv[5]}, {len(rows) // 2} run(s) each, alternated")
print("build | s/image min | s/image median | s/MP min | CPU s/image min | CPU s/image median | 2-core s/image (CPU/2) "
      "| images | MP/image | features/image | runs (s) | load at the runs' ends")
res, cpu = {}, {}
for b in "AB":
    t = [float(r[1]) for r in rows if r[0] == b]
    c = [float(r[5]) for r in rows if r[0] == b]
    loads = [r[6] for r in rows if r[0] == b]
    r0 = next(r for r in rows if r[0] == b)
    n, mp = int(r0[2]), float(r0[3])
    res[b], cpu[b] = min(t) / n, min(c) / n
    print(f"{b} | {min(t) / n:.3f} | {statistics.median(t) / n:.3f} | {min(t) / mp:.4f} | {min(c) / n:.3f} | "
          f"{statistics.median(c) / n:.3f} | {min(c) / n / 2:.3f} | {n} | {mp / n:.2f} | "
          f"{float(r0[4]):.0f} | {' '.join(f'{x:.2f}' for x in t)} | {' '.join(loads)}")
print(f"ratio B/A (min s/image): {res['B'] / res['A']:.3f}; (min CPU s/image): {cpu['B'] / cpu['A']:.3f}")
PY
