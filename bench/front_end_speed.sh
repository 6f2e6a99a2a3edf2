#!/usr/bin/env bash
# Front-end speed and accuracy, variants of pgba side by side in one run (the same moment of
# a shared machine, so their ratios are meaningful even when absolute times are not):
#   before   the front end without pgba's own parts: OpenCV SIFT, FLANN kd-forest (4 trees,
#            32 checks), no buffer reuse between images (features.reuse_buffers false)
#   kdtree   the defaults but the kd-forest instead of cascade hashing
#   default  the defaults (buffer reuse, cascade hashing, SIFT "auto": pgba's from 0.5 MP,
#            OpenCV's below)
#   opencv   defaults + features.sift.implementation "opencv" (OpenCV 4.6's SIFT, the
#            same algorithm as pgba's, its pyramid on one thread)
#   pgba     defaults + features.sift.implementation "pgba" (pgba's own SIFT, parallel
#            inside one image, by default one image at a time)
#   pgba2    pgba with two images in flight (features.max_parallel_images 2): each image's
#            inner parallel loops, and the other image's work where a thread would wait
#   octave0  defaults + features.sift.first_octave 0 (no upsampled octave: faster, fewer
#            fine-scale keypoints; its accuracy cost is what this measures)
# Each variant runs `pgba run --gt` from scratch (no feature cache); the variants of one
# dataset run back to back, in the order given, then again in reverse (REPEAT=2, default) and
# the times are averaged, so a load change on the machine hits every variant alike.
# Prints one table: s per image and per megapixel for features, ms per pair for matching
# (wall time over pairs, and the thread time of descriptor matching and verification per
# pair), verified pairs and inliers, total time, and the rotation errors against the
# ground truth. CPU time (user + system of every thread, report.json's cpu_seconds) per image
# and per pair beside the wall times: on a shared machine the others' load stretches the wall
# time, the CPU time far less. The targets on 2 cores, <= 1 s per 6 MP image and <= 15 ms
# per pair, are <= 2 s and <= 30 ms of CPU time when both cores work.
#
# A variant whose run fails (e.g. no triplet on a weakly textured ring) is reported with 0
# registered images and the error; the table still shows its front-end numbers.
#
# Usage: bench/front_end_speed.sh [DATASET_DIR ...]  (default: fountain_p11 herzjesu_p8 entry_p10)
# Environment: PGBA=path/to/pgba (default: newest build*/bin/pgba), VARIANTS="before default"
#   (default: before default octave0), REPEAT=1|2, PGBA_BASE=path/to/another/pgba adds a
#   variant "base" run with that binary and the default config (for example another branch's build).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
shared=$(cd "$here/.." && pwd)/shared
source "$here/bench/pgba_binary.sh"
if [[ $# -eq 0 ]]; then
  set -- "$shared/datasets/fountain_p11" "$shared/datasets/herzjesu_p8" "$shared/datasets/entry_p10"
fi
read -r -a variants <<<"${VARIANTS:-before default octave0}"
[[ -n "${PGBA_BASE:-}" ]] && variants=(base "${variants[@]}")
repeat=${REPEAT:-2}
tmp=$(mktemp -d /tmp/pgba_front_speed_XXXX)
trap 'rm -rf "$tmp"' EXIT
echo '{"matching": {"descriptors": {"method": "kdtree"}}}' >"$tmp/kdtree.json"
echo '{"features": {"reuse_buffers": false, "sift": {"implementation": "opencv"}}, "matching": {"descriptors": {"method": "kdtree"}}}' >"$tmp/before.json"
echo '{}' >"$tmp/default.json"
echo '{"features": {"sift": {"implementation": "opencv"}}}' >"$tmp/opencv.json"
echo '{"features": {"sift": {"implementation": "pgba"}}}' >"$tmp/pgba.json"
echo '{"features": {"max_parallel_images": 2, "sift": {"implementation": "pgba"}}}' >"$tmp/pgba2.json"
echo '{"features": {"sift": {"first_octave": 0}}}' >"$tmp/octave0.json"
cp "$tmp/default.json" "$tmp/base.json"

run_variant() {  # DATASET VARIANT ROUND
  local ds=$1 v=$2 round=$3 bin=$PGBA
  [[ $v == base ]] && bin=$PGBA_BASE
  [[ -f "$tmp/$v.json" ]] || { echo "error: unknown variant '$v' (before, kdtree, default, opencv, pgba, pgba2, octave0)" >&2; exit 2; }
  local out="$tmp/$(basename "$ds")_${v}_$round"
  # The whole process' wall and CPU time (of any build, also one whose report.json has no
  # cpu_seconds), and the load average after the run.
  /usr/bin/time -f "%e %U %S" -o "$out.time" "$bin" -v 0 run --images "$ds/images" --calib "$ds/cameras.txt" \
    --gt "$ds/gt" --config "$tmp/$v.json" --out "$out" >"$out.log" 2>&1 ||
    { echo "warning: $v on $(basename "$ds") failed: $(grep -m1 error "$out.log")" >&2; }
  cut -d' ' -f1 /proc/loadavg >"$out.load"
}

for ds in "$@"; do
  [[ -d "$ds/images" && -f "$ds/cameras.txt" && -d "$ds/gt" ]] || { echo "error: $ds: needs images/, cameras.txt, gt/" >&2; exit 2; }
  order=("${variants[@]}")
  for ((r = 1; r <= repeat; r++)); do
    for v in "${order[@]}"; do run_variant "$ds" "$v" "$r"; done
    reversed=(); for ((i = ${#order[@]} - 1; i >= 0; i--)); do reversed+=("${order[i]}"); done; order=("${reversed[@]}")
  done
done

echo "Front end on $(nproc) cores, load average at the end: $(cut -d' ' -f1-3 /proc/loadavg); times averaged over $repeat run(s)"
echo
python3 - "$tmp" "$repeat" "${variants[@]}" -- "$@" <<'PY'
import json, os, sys
tmp, repeat = sys.argv[1], int(sys.argv[2])
sep = sys.argv.index("--")
variants, datasets = sys.argv[3:sep], sys.argv[sep + 1:]
print("dataset | variant | s/image features | CPU s/image features | s/MP features | ms/pair matching (wall) "
      "| CPU ms/pair matching | CPU ms/pair descriptors | CPU ms/pair verification | verified pairs | verified matches "
      "| total s | process wall s | process CPU s | load after | registered | rot err median deg | rot err max deg")
print("|".join(["---"] * 18))
for ds in datasets:
    name = os.path.basename(ds.rstrip("/"))
    for v in variants:
        reps = [json.load(open(f"{tmp}/{name}_{v}_{r}/report.json")) for r in range(1, repeat + 1)]
        failed = [x.get("error", "failed") for x in reps if x.get("status") != "ok"]
        mean = lambda f: sum(f(x) for x in reps) / len(reps)
        st = lambda x: x["stages"]
        f0, m0, e0 = st(reps[0])["features"], st(reps[0])["match"], reps[0].get("evaluation", {})
        if failed:
            e0 = {"images_registered": 0, "failed": failed[0][:60]}
        total = mean(lambda x: sum(s.get("seconds", 0) for s in st(x).values() if isinstance(s, dict)))
        proc = [list(map(float, open(f"{tmp}/{name}_{v}_{r}.time").read().split()[-3:])) for r in range(1, repeat + 1)]
        wall = sum(p[0] for p in proc) / repeat
        cpu = sum(p[1] + p[2] for p in proc) / repeat
        loads = "/".join(open(f"{tmp}/{name}_{v}_{r}.load").read().strip() for r in range(1, repeat + 1))
        nan = float("nan")
        print(f"{name} | {v} | {mean(lambda x: st(x)['features']['seconds']) / f0['images']:.2f} | "
              f"{mean(lambda x: st(x)['features'].get('cpu_seconds', nan)) / f0['images']:.2f} | "
              f"{mean(lambda x: st(x)['features']['seconds_per_megapixel']):.3f} | "
              f"{1000 * mean(lambda x: st(x)['match']['seconds_per_pair']):.1f} | "
              f"{1000 * mean(lambda x: st(x)['match'].get('cpu_seconds_per_pair', nan)):.1f} | "
              f"{1000 * mean(lambda x: st(x)['match'].get('cpu_seconds_per_pair_descriptors', nan)):.1f} | "
              f"{1000 * mean(lambda x: st(x)['match'].get('cpu_seconds_per_pair_verification', nan)):.1f} | "
              f"{m0['pairs_verified']}/{m0['pairs']} | {m0['verified_matches']} | {total:.1f} | {wall:.1f} | {cpu:.1f} | "
              f"{loads} | "
              f"{e0.get('images_registered', '?')}/{f0['images']}{' (failed: ' + e0['failed'] + ')' if 'failed' in e0 else ''} | {e0.get('rot_err_deg_median', float('nan')):.4f} | "
              f"{e0.get('rot_err_deg_max', float('nan')):.4f}")
PY
