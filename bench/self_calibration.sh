#!/usr/bin/env bash
# Self-calibration (issue 14's acceptance table), against the same scene given its true
# calibration (held). Two kinds of scene, both through a lens with radial distortion K1 and
# handed a calibration with the focal off by E and k = 0:
#   orbit:SEED, aerial:SEED, ... synthetic tracks (`pgba synth --scenario`), given to `pgba
#     reconstruct` (view-graph focal estimate and intrinsics as unknowns of every adjustment:
#     config calibration.cameras = all, intrinsics.cameras = all);
#   rendered:SEED  rendered photographs (`pgba synth --render`), given to `pgba run` with
#     --calib-prior (every BA refines focal and k; the images are matched again with the
#     refined cameras, calibration.rematch_shift_px). The reference run reuses its features.
# One row per scene: images registered, refined focal error (%), k1 error, median relative
# rotation error over all pairs (gauge-free, `pgba evaluate`'s rel_rot_err_deg_median) of both
# runs and their ratio. Issue 14's bars: focal within 0.3%, k1 within 0.005, ratio <= 1.2.
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
cat >"$out/self_calibration.json" <<'EOF2'
{"calibration": {"cameras": "all"}, "intrinsics": {"cameras": "all"}}
EOF2

# Leaves DIR/run_prior, DIR/run_true (each with sparse/ and tracks/) and DIR/gt.
tracks_scene() {  # DIR KIND SEED
  local dir=$1
  "$PGBA" synth --scenario "$2" --seed "$3" --outliers 0.02 --k1 "$k1" --focal-prior-error "$e" \
    --out "$dir/prior" >/dev/null
  "$PGBA" synth --scenario "$2" --seed "$3" --outliers 0.02 --k1 "$k1" --out "$dir/true" >/dev/null
  cp "$dir/true/gt/cameras.txt" "$dir/true/input/cameras.txt"  # synth's input holds k = 0: give it the lens
  "$PGBA" reconstruct --tracks "$dir/prior/input" --config "$out/self_calibration.json" --out "$dir/run_prior" \
    >"$dir/run_prior.log" 2>&1
  "$PGBA" reconstruct --tracks "$dir/true/input" --out "$dir/run_true" >"$dir/run_true.log" 2>&1
  ln -sfn ../prior/input "$dir/run_prior/tracks_used"
  ln -sfn ../true/input "$dir/run_true/tracks_used"
  ln -sfn prior/gt "$dir/gt"
}
rendered_scene() {  # DIR SEED
  local dir=$1
  "$PGBA" synth --render --seed "$2" --k1 "$k1" --focal-prior-error "$e" --out "$dir/scene" >/dev/null
  "$PGBA" run --images "$dir/scene/images" --calib "$dir/scene/gt/cameras.txt" --out "$dir/run_true" \
    >"$dir/run_true.log" 2>&1
  mkdir -p "$dir/run_prior"
  cp -r "$dir/run_true/features" "$dir/run_prior/"  # same photos and options: cached features
  "$PGBA" run --images "$dir/scene/images" --calib "$dir/scene/cameras.txt" --calib-prior --out "$dir/run_prior" \
    >"$dir/run_prior.log" 2>&1
  ln -sfn tracks "$dir/run_prior/tracks_used"
  ln -sfn tracks "$dir/run_true/tracks_used"
  ln -sfn scene/gt "$dir/gt"
}

printf "%-11s %6s %10s %10s %12s %12s %7s\n" scene reg "focal %" "k1 err" "rel.rot deg" "true cal." ratio
for scene in "${scenes[@]}"; do
  IFS=: read -r kind seed <<<"$scene"
  dir=$out/${kind}_$seed
  mkdir -p "$dir"
  if [[ $kind == rendered ]]; then rendered_scene "$dir" "$seed"; else tracks_scene "$dir" "$kind" "$seed"; fi
  for run in run_prior run_true; do
    "$PGBA" evaluate "$dir/$run/sparse" --obs "$dir/$run/tracks_used" --gt "$dir/gt" --json "$dir/$run/eval.json" \
      >/dev/null
  done
  python3 - "$dir" "$scene" <<'EOF2'
import json, sys
d, scene = sys.argv[1], sys.argv[2]
def cam(path):
    for line in open(path):
        if line.strip() and not line.startswith('#'):
            p = line.split()
            return p[1], [float(x) for x in p[4:]]
(model, est), (gt_model, gt) = cam(d + "/run_prior/sparse/cameras.txt"), cam(d + "/gt/cameras.txt")
radial = ('SIMPLE_RADIAL', 'RADIAL')
k_est = est[3] if model in radial else float('nan')
k_gt = gt[3] if gt_model in radial else 0.0
a, b = (json.load(open(d + "/" + run + "/eval.json")) for run in ("run_prior", "run_true"))
ra, rb = a["rel_rot_err_deg_median"], b["rel_rot_err_deg_median"]
reg = "%d/%d" % (a["images_registered"], a["images_input"])
print("%-11s %6s %+10.3f %+10.4f %12.5f %12.5f %7.3f" % (scene, reg, 100 * (est[0] / gt[0] - 1), k_est - k_gt,
                                                         ra, rb, ra / rb))
EOF2
done
