#!/usr/bin/env bash
# Matching of two builds against each other in one run: `pgba run --gt` alternately with
# build A and build B, REPS times each, on the same cached features (extracted once by build
# B, so that only matching and what follows differ), and per build the minimum over the runs
# of the matching wall time and thread times per pair, with the verified pairs and matches
# and the rotation errors against the ground truth (deterministic, so from any run).
# Alternating and taking minima keeps a shared machine's load out of the comparison; the load
# average is printed with each dataset.
# CPU time (user + system): of the process over the pair loop per pair ("CPU ms/pair", the
# cost on a machine whose other load only delays it; the target, <= 15 ms per pair on 2
# cores, is <= 30 ms of it when both cores match), and of each pair's thread over its
# descriptor search and its verification.
#
# MATCH_ONLY=1: `pgba match` instead of `pgba run` (seconds instead of minutes per run; no
# rotation errors), and whether A's and B's matching outputs (verified geometries, per-pair
# table, tracks) are byte-identical.
#
# Usage: bench/match_ab.sh PGBA_A PGBA_B REPS [DATASET_DIR ...]
#   (default datasets: fountain_p11 herzjesu_p8 entry_p10 of ../shared/datasets)
set -euo pipefail
if [[ $# -lt 3 ]]; then echo "usage: $0 PGBA_A PGBA_B REPS [DATASET_DIR ...]" >&2; exit 2; fi
a=$1 b=$2 reps=$3
shift 3
here=$(cd "$(dirname "$0")/.." && pwd)
shared=$(cd "$here/.." && pwd)/shared
if [[ $# -eq 0 ]]; then
  set -- "$shared/datasets/fountain_p11" "$shared/datasets/herzjesu_p8" "$shared/datasets/entry_p10"
fi
[[ -x "$a" && -x "$b" ]] || { echo "error: $a or $b is not an executable" >&2; exit 2; }
tmp=$(mktemp -d /tmp/pgba_match_ab_XXXX)
trap 'rm -rf "$tmp"' EXIT
echo "dataset | build | ms/pair matching (wall, min) | CPU ms/pair (min) | CPU ms/pair descriptors (min) | CPU ms/pair verification (min) | verified pairs | verified matches | rot err median deg | rot err max deg | load (1 min) at end"
echo "---|---|---|---|---|---|---|---|---|---|---"
for ds in "$@"; do
  name=$(basename "$ds")
  "$b" -v 0 features --images "$ds/images" --calib "$ds/cameras.txt" --out "$tmp/feat_$name" >/dev/null
  for ((r = 1; r <= reps; ++r)); do
    for build in A B; do
      bin=$a; [[ $build == B ]] && bin=$b
      out="$tmp/${name}_${build}_$r"
      cp -r "$tmp/feat_$name" "$out"
      if [[ "${MATCH_ONLY:-0}" == 1 ]]; then
        "$bin" -v 0 match --out "$out" >"$out.log" 2>&1 || echo "warning: $build on $name failed (log $out.log)" >&2
      else
        "$bin" -v 0 run --images "$ds/images" --calib "$ds/cameras.txt" --gt "$ds/gt" --out "$out" >"$out.log" 2>&1 ||
          echo "warning: $build on $name failed (log $out.log)" >&2
      fi
    done
  done
  same=no
  diff -rq "$tmp/${name}_A_1/matching" "$tmp/${name}_B_1/matching" >/dev/null &&
    diff -rq "$tmp/${name}_A_1/tracks" "$tmp/${name}_B_1/tracks" >/dev/null && same=yes
  echo "$name: A's and B's matching outputs (matching/, tracks/) byte-identical: $same" >&2
  python3 - "$tmp" "$name" "$reps" "$(cut -d' ' -f1 /proc/loadavg)" <<'PY'
import json, sys
tmp, name, reps, load = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
for build in "AB":
    rs = [json.load(open(f"{tmp}/{name}_{build}_{r}/report.json")) for r in range(1, reps + 1)]
    m = [x["stages"]["match"] for x in rs]
    e = rs[0].get("evaluation", {})
    mn = lambda k: 1000 * min(x.get(k, float("nan")) for x in m)
    print(f"{name} | {build} | {mn('seconds_per_pair'):.1f} | {mn('cpu_seconds_per_pair'):.1f} | "
          f"{mn('cpu_seconds_per_pair_descriptors'):.1f} | {mn('cpu_seconds_per_pair_verification'):.1f} | "
          f"{m[0]['pairs_verified']}/{m[0]['pairs']} | "
          f"{m[0]['verified_matches']} | {e.get('rot_err_deg_median', float('nan')):.4f} | "
          f"{e.get('rot_err_deg_max', float('nan')):.4f} | {load}")
PY
done
