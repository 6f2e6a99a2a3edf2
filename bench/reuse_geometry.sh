#!/usr/bin/env bash
# The view graph from the front end's verified geometries (pairs.front_end) and the cost of
# `pgba run`'s convergence curve, measured in one run:
#   base       PGBA_BASE (another build to compare with), `pgba run --gt` from scratch
#   default    this build, `pgba run --gt` from scratch (pairs.front_end "refine")
# then, on copies of default's workspace (features and tracks cached, so only the stages
# from the view graph on run again; their times compare with each other):
#   estimate   pairs.front_end "estimate": RANSAC on every candidate, the front end's geometry unused
#   reuse      pairs.front_end "reuse": the front end's geometries as they are
#   refine     pairs.front_end "refine" (the default)
#   refine_fe  "refine" with pairs.track_only_pairs false: only the front end's pairs
# Prints per-stage seconds (report.json), the view graph's counts and the rotation errors
# against the ground truth (Sim(3)-aligned, and the gauge-free relative ones).
# Usage: PGBA_BASE=/path/to/other/pgba bench/reuse_geometry.sh [DATASET_DIR ...]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
shared=$(cd "$here/.." && pwd)/shared
PGBA=${PGBA:-$here/build/bin/pgba}
[[ -x "$PGBA" && -x "${PGBA_BASE:-}" ]] || { echo "error: set PGBA_BASE (and PGBA) to pgba binaries" >&2; exit 2; }
[[ $# -eq 0 ]] && set -- "$shared/datasets/fountain_p11" "$shared/datasets/herzjesu_p8" "$shared/datasets/entry_p10"
tmp=${OUT:-$(mktemp -d /tmp/pgba_reuse_XXXX)}
mkdir -p "$tmp"
echo '{}' >"$tmp/default.json"
echo '{"pairs": {"front_end": "estimate"}}' >"$tmp/estimate.json"
echo '{"pairs": {"front_end": "reuse"}}' >"$tmp/reuse.json"
echo '{"pairs": {"front_end": "refine"}}' >"$tmp/refine.json"
echo '{"pairs": {"front_end": "refine", "track_only_pairs": false}}' >"$tmp/refine_fe.json"
run() {  # BIN DATASET VARIANT OUT
  "$1" -v 0 run --images "$2/images" --calib "$2/cameras.txt" --gt "$2/gt" --config "$tmp/$3.json" --out "$4" \
    >"$4.log" 2>&1 || echo "warning: $3 on $(basename "$2") failed: $(grep -m1 error "$4.log")" >&2
}
for ds in "$@"; do
  name=$(basename "$ds")
  run "$PGBA_BASE" "$ds" default "$tmp/${name}_base"
  run "$PGBA" "$ds" default "$tmp/${name}_default"
  for v in estimate reuse refine refine_fe; do
    rm -rf "$tmp/${name}_$v"
    mkdir -p "$tmp/${name}_$v"
    cp -r "$tmp/${name}_default/features" "$tmp/${name}_default/tracks" "$tmp/${name}_default/matching" "$tmp/${name}_$v/"
    run "$PGBA" "$ds" "$v" "$tmp/${name}_$v"
  done
done
echo "$(nproc) cores, load average at the end: $(cut -d' ' -f1-3 /proc/loadavg); outputs in $tmp"
python3 - "$tmp" -- "$@" <<'PY'
import json, os, sys
tmp = sys.argv[1]
datasets = sys.argv[3:]
stages = ["features", "match", "pairs", "triplets", "global_init", "local_hessians", "global_ba", "convergence", "triangulation"]
print("| dataset | variant | " + " | ".join(s + " s" for s in stages) + " | total s | pairs kept / examined | from front end | RANSAC | registered | rot err median / max deg | rel rot err median / max deg |")
print("|" + "---|" * (len(stages) + 9))
for ds in datasets:
    name = os.path.basename(ds.rstrip("/"))
    for v in ["base", "default", "estimate", "reuse", "refine", "refine_fe"]:
        path = f"{tmp}/{name}_{v}/report.json"
        if not os.path.exists(path):
            continue
        r = json.load(open(path))
        st = r.get("stages", {})
        sec = [st.get(s, {}).get("seconds", 0.0) for s in stages]
        p = st.get("pairs", {})
        e = r.get("evaluation", {})
        print(f"| {name} | {v} | " + " | ".join(f"{x:.2f}" for x in sec) + f" | {sum(sec):.1f} | "
              f"{p.get('pairs_kept', '')} / {p.get('pairs_estimated', '')} | {p.get('pairs_front_end', 0)} | "
              f"{p.get('pairs_ransac', p.get('pairs_estimated', ''))} | {e.get('images_registered', 0)} | "
              f"{e.get('rot_err_deg_median', float('nan')):.4f} / {e.get('rot_err_deg_max', float('nan')):.4f} | "
              f"{e.get('rel_rot_err_deg_median', float('nan')):.4f} / {e.get('rel_rot_err_deg_max', float('nan')):.4f} |")
PY
