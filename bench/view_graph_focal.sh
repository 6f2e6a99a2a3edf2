#!/usr/bin/env bash
# The view-graph focal estimate (modules/calibration) against exact truths:
#   synthetic tracks (orbit, aerial; seeds 1-2), true lens k1 -0.08, input focal prior +-15%:
#     pgba synth ... then pgba init with calibration.cameras = "all" (input/ is a file prior);
#   real sets without their cameras.txt (prior 1.2 x max(w, h)): pgba run on a copy of the
#     image folder (the Strecha JPEGs carry no EXIF), focal vs the dataset's calibration.
# Usage: bash bench/view_graph_focal.sh OUT_DIR [--no-real]
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:?usage: bench/view_graph_focal.sh OUT_DIR [--no-real]}
B=build/bin/pgba
DATA=../shared/datasets
mkdir -p "$OUT"
echo '{"calibration": {"cameras": "all"}}' > "$OUT/all.json"
report() {  # report.json, true focal, label
  python3 -c "
import json, sys
c = json.load(open('$1'))['stages']['focal_estimation']['cameras'][0]
print('%-26s prior %7.1f  estimate %7.1f  truth %7.1f  error %+6.2f%%  sd %.3f  k1 %+.4f  pairs %3d  %s' % (
    '$3', c['prior_focal'], c['estimated_focal'], $2, 100 * (c['estimated_focal'] / $2 - 1), c['relative_sd'] or -1,
    c['estimated_k1'], c['pairs_used'], 'applied' if c['applied'] else 'kept the prior: ' + c['reason']))"
}
for sc in orbit aerial; do for seed in 1 2; do for e in 0.15 -0.15; do
  d="$OUT/${sc}_s${seed}_e${e}"
  $B synth --scenario $sc --seed $seed --k1 -0.08 --focal-prior-error $e --out "$d" > /dev/null
  $B init --tracks "$d/input" --out "$d/init" --config "$OUT/all.json" > /dev/null 2>&1
  truth=$(grep -v '^#' "$d/gt/cameras.txt" | awk '{print $5}')
  report "$d/init/report.json" "$truth" "${sc} seed ${seed} prior ${e}"
done; done; done
[ "${2:-}" = "--no-real" ] && exit 0
for set in entry_p10 fountain_p11 herzjesu_p8; do
  d="$OUT/$set"
  mkdir -p "$d/images"
  for f in "$DATA/$set/images/"*; do ln -sf "$(realpath "$f")" "$d/images/"; done
  $B run --images "$d/images" --gt "$DATA/$set/gt" --out "$d/run" > "$d/run.log" 2>&1
  truth=$(grep -v '^#' "$DATA/$set/cameras.txt" | awk '{print 0.5 * ($5 + $6)}')
  report "$d/run/report.json" "$truth" "$set (no calibration)"
done
