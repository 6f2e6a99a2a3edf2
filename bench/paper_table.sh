#!/usr/bin/env bash
# The paper's Table 1 (reprojection errors sigma_init / sigma_final and unknowns) for one
# dataset in the layout of datasets/README.md (images/, cameras.txt, [camera_map.txt], gt/):
#   1. pgba run        --images DATASET/images --out OUT/run      (features, matching, tracks)
#   2. pgba benchmark  --tracks OUT/run/tracks --gt DATASET/gt --out OUT/benchmark
#      (pointless BA, point-based BA and Aver_BA from one shared initialisation)
#   3. prints Table 1 from OUT/benchmark/benchmark.json in the paper's layout, plus the
#      ground-truth rotation error.
# Never run by the unit tests (it needs a downloaded dataset and minutes of CPU).
#
# Usage: bench/paper_table.sh DATASET_DIR OUT
# Environment: PGBA=path/to/pgba (default: the newest build*/bin/pgba of this checkout),
#   CONFIG=configs/X.json (passed to run and benchmark; default: none = documented defaults),
#   LOOP=loop_pairs.txt (withheld loop correspondences for Table 2; default DATASET/loop_pairs.txt
#   if present).
set -euo pipefail
if [[ $# -ne 2 ]]; then
  echo "usage: $0 DATASET_DIR OUT" >&2
  exit 2
fi
ds=$1
out=$2
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/pgba_binary.sh"
for need in images cameras.txt gt/images.txt; do
  [[ -e "$ds/$need" ]] || { echo "error: $ds/$need missing (see datasets/README.md for the layout)" >&2; exit 2; }
done
command -v python3 >/dev/null || { echo "error: python3 is needed to print the table" >&2; exit 2; }

run_args=(--images "$ds/images" --calib "$ds/cameras.txt" --out "$out/run" --gt "$ds/gt")
[[ -f "$ds/camera_map.txt" ]] && run_args+=(--camera-map "$ds/camera_map.txt")
bench_args=(--tracks "$out/run/tracks" --gt "$ds/gt" --out "$out/benchmark")
if [[ -n "${CONFIG:-}" ]]; then
  run_args+=(--config "$CONFIG")
  bench_args+=(--config "$CONFIG")
fi
loop=${LOOP:-$ds/loop_pairs.txt}
[[ -f "$loop" ]] && bench_args+=(--loop "$loop")

mkdir -p "$out"
echo "== pgba run ($ds)" >&2
"$PGBA" run "${run_args[@]}" >"$out/run.stdout"
echo "== pgba benchmark" >&2
"$PGBA" benchmark "${bench_args[@]}" >"$out/benchmark.stdout"

python3 - "$out/benchmark/benchmark.json" "$(basename "$ds")" "$out/run/report.json" <<'PY'
import json, math, sys
path, name, run_report = sys.argv[1], sys.argv[2], sys.argv[3]
methods = json.load(open(path))["methods"]
def num(v, fmt):
    return fmt.format(v) if isinstance(v, (int, float)) and math.isfinite(v) else "--"
rows = [("Ours_BA (pointless)", "pointless"), ("point-based BA", "pointbased"), ("Aver_BA", "averaging")]
print(f"\nTable 1: {name} (sigma in px, #params in thousands of unknowns)")
print(f"{'Method':<22} {'sigma_init':>10} {'sigma_final':>11} {'#params':>9} {'rot_err_med_deg':>16} {'adjust_s':>9}")
for label, key in rows:
    m = methods.get(key)
    if m is None:
        print(f"{label:<22} {'(not run)':>10}")
        continue
    print(f"{label:<22} {num(m.get('sigma_init'), '{:.2f}'):>10} {num(m.get('sigma_final'), '{:.2f}'):>11} "
          f"{num(m.get('params', float('nan')) / 1000.0, '{:,.0f}k' if m.get('params', 0) >= 10000 else '{:.2f}k'):>9} "
          f"{num(m.get('rot_err_deg_median'), '{:.4f}'):>16} {num(m.get('adjust_seconds'), '{:.2f}'):>9}")
run = json.load(open(run_report))
print(f"images registered by pgba run: {run.get('images_registered', '?')} / {run.get('images_input', '?')}")
PY
echo "full tables: $out/benchmark.stdout; report: $out/run/report.html" >&2
