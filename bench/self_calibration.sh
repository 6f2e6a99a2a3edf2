#!/usr/bin/env bash
# Self-calibration (issue 14's acceptance table): synthetic track scenes through a lens with
# radial distortion K1, given to `pgba reconstruct` with the focal prior off by E and k = 0
# (view-graph focal estimate and intrinsics as unknowns of every adjustment: config
# calibration.cameras = all, intrinsics.cameras = all), against the same scene given its true
# calibration (held). One row per scene: refined focal error (%), k1 error, median relative
# rotation error over all pairs (gauge-free) of both runs and their ratio.
#
# Usage: bench/self_calibration.sh OUT [SCENE:SEED...]    (default: orbit:1 orbit:2 aerial:1 aerial:2)
# Environment: PGBA (default: newest build*/bin/pgba), K1 (default -0.08), E (default 0.15).
set -euo pipefail
if [[ $# -lt 1 ]]; then
  echo "usage: $0 OUT [SCENE:SEED...]" >&2
  exit 2
fi
out=$1
shift
here=$(cd "$(dirname "$0")/.." && pwd)
if [[ -z "${PGBA:-}" ]]; then
  PGBA=$(ls -t "$here"/build*/bin/pgba 2>/dev/null | head -1 || true)
fi
[[ -x "${PGBA:-}" ]] || { echo "error: pgba binary not found; build it or set PGBA=" >&2; exit 2; }
k1=${K1:--0.08}
e=${E:-0.15}
scenes=("$@")
[[ ${#scenes[@]} -eq 0 ]] && scenes=(orbit:1 orbit:2 aerial:1 aerial:2)
mkdir -p "$out"
cat >"$out/self_calibration.json" <<'EOF'
{"calibration": {"cameras": "all"}, "intrinsics": {"cameras": "all"}}
EOF

rel_rot() {  # MODEL INPUT GT -> median relative rotation error (deg)
  "$PGBA" evaluate "$1" --obs "$2" --gt "$3" --json "$1/../eval.json" >/dev/null
  python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['rel_rot_err_deg_median'])" "$1/../eval.json"
}

printf "%-10s %10s %10s %12s %12s %7s\n" scene "focal %" "k1 err" "rel.rot deg" "true cal." ratio
for scene in "${scenes[@]}"; do
  IFS=: read -r kind seed <<<"$scene"
  dir=$out/${kind}_$seed
  "$PGBA" synth --scenario "$kind" --seed "$seed" --outliers 0.02 --k1 "$k1" --focal-prior-error "$e" \
    --out "$dir/prior" >/dev/null
  "$PGBA" synth --scenario "$kind" --seed "$seed" --outliers 0.02 --k1 "$k1" --out "$dir/true" >/dev/null
  cp "$dir/true/gt/cameras.txt" "$dir/true/input/cameras.txt"  # synth's input holds k = 0: give it the lens
  "$PGBA" reconstruct --tracks "$dir/prior/input" --config "$out/self_calibration.json" --out "$dir/run_prior" \
    >"$dir/run_prior.log" 2>&1
  "$PGBA" reconstruct --tracks "$dir/true/input" --out "$dir/run_true" >"$dir/run_true.log" 2>&1
  a=$(rel_rot "$dir/run_prior/sparse" "$dir/prior/input" "$dir/prior/gt")
  b=$(rel_rot "$dir/run_true/sparse" "$dir/true/input" "$dir/true/gt")
  python3 - "$dir/run_prior/sparse/cameras.txt" "$dir/prior/gt/cameras.txt" "$scene" "$a" "$b" <<'EOF'
import sys
def cam(path):
    for line in open(path):
        if line.strip() and not line.startswith('#'):
            p = line.split()
            return p[1], [float(x) for x in p[4:]]
(model, est), (gt_model, gt) = cam(sys.argv[1]), cam(sys.argv[2])
k_est = est[3] if model == 'SIMPLE_RADIAL' else float('nan')
k_gt = gt[3] if gt_model == 'SIMPLE_RADIAL' else 0.0
a, b = float(sys.argv[4]), float(sys.argv[5])
print("%-10s %+10.3f %+10.4f %12.5f %12.5f %7.3f" % (sys.argv[3], 100 * (est[0] / gt[0] - 1), k_est - k_gt, a, b, a / b))
EOF
done
