#!/usr/bin/env bash
# Self-calibration on synthetic scenes (docs/benchmarks.md): the pointless BA with the intrinsics
# as unknowns against the same scene given its true calibration (held), and against the
# point-based BA with the same unknowns on the same tracks, which is the maximum-likelihood
# estimate there: where even it misses a bar, no estimator meets it on that geometry.
# Every scene goes through a lens with radial distortion K1 and is handed a calibration with
# the focal off by E and k = 0:
#   orbit:SEED, aerial:SEED, planar:SEED, longfocal:SEED  synthetic tracks (`pgba synth
#     --scenario`, 0.5 px noise, 2% outliers), each given to `pgba benchmark` three times:
#       calibrated   the tracks with the true lens (held): pointless and point-based;
#       self-cal.    the prior tracks with config self_calibration.json (view-graph focal
#                    estimate, intrinsics unknowns of every adjustment): pointless (the same
#                    run as `pgba reconstruct` with that config: measured equal to the digit on
#                    aerial:1) and point-based at their default tolerances;
#       converged    the same with every tolerance at 1e-12 (point-based up to 500 iterations,
#                    up to 20 re-linearisation passes): where both BAs end when they are not
#                    stopped early in the focal-height valley.
#   rendered:SEED  rendered photographs (`pgba synth --render`), `pgba run` with the true
#     calibration (--calib gt) and with the prior (--calib-prior: every BA refines focal and k;
#     the images are matched again with the refined cameras); then `pgba benchmark` on the
#     prior run's final tracks with the intrinsics free (what the run's last BA started from)
#     and on the calibrated run's tracks.
# One row per scene and method: refined focal error (%), k1 error, median relative rotation
# error over all pairs (gauge-free, rel_rot_err_deg_median) and its ratio to the calibrated
# pointless run. The targets: focal within 0.3%, k1 within 0.005, ratio <= 1.2.
#
# Usage: bench/self_calibration.sh OUT [SCENE:SEED...]
#   default: orbit, aerial and planar at seeds 1-4, rendered:1.
# Environment: PGBA (default: newest build*/bin/pgba), K1 (default -0.08), E (default 0.15),
#   CONFIG (extra config merged into every self-calibrating run, e.g. global_ba options),
#   CONVERGED (default 1: 0 skips the converged runs), TABLE_ONLY (1: only print the table of
#   the runs already in OUT).
set -euo pipefail
if [[ $# -lt 1 ]]; then
  echo "usage: $0 OUT [SCENE:SEED...]" >&2
  exit 2
fi
out=$1
shift
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/pgba_binary.sh"
k1=${K1:--0.08}
e=${E:-0.15}
converged=${CONVERGED:-1}
scenes=("$@")
if [[ ${#scenes[@]} -eq 0 ]]; then
  for s in orbit aerial planar; do
    for seed in 1 2 3 4; do scenes+=("$s:$seed"); done
  done
  scenes+=(rendered:1)
fi
mkdir -p "$out"
# Config files: the self-calibrating one (CONFIG merged in), the converged one, the calibrated one.
python3 - "$out" "${CONFIG:-}" <<'EOF'
import json, sys
out, extra = sys.argv[1], sys.argv[2]
def merge(a, b):
    for k, v in b.items():
        a[k] = merge(a.get(k, {}), v) if isinstance(v, dict) else v
    return a
base = json.load(open(extra)) if extra else {}
selfcal = merge(json.loads(json.dumps(base)), {"calibration": {"cameras": "all"}, "intrinsics": {"cameras": "all"}})
tight = merge(json.loads(json.dumps(selfcal)), {
    "point_based": {"bundle": {"function_tolerance": 1e-12, "parameter_tolerance": 1e-14, "max_iterations": 500}},
    "global_ba": {"function_tolerance": 1e-12, "parameter_tolerance": 1e-14, "relinearize_cost_tolerance": 1e-12,
                  "relinearize_tolerance": 1e-6, "max_relinearizations": 20}})
rendered = merge(json.loads(json.dumps(base)), {"intrinsics": {"cameras": "all"}})
for name, c in (("self_calibration", selfcal), ("converged", tight), ("rendered_tracks", rendered),
                ("calibrated", base)):
    json.dump(c, open(f"{out}/{name}.json", "w"))
EOF

bench() {  # TRACKS GT CONFIG OUT
  "$PGBA" benchmark --tracks "$1" --gt "$2" --config "$3" --no-convergence --out "$4" >"$4.log" 2>&1 ||
    echo "benchmark failed: $4.log" >&2
}
tracks_scene() {  # DIR KIND SEED
  local dir=$1
  "$PGBA" synth --scenario "$2" --seed "$3" --outliers 0.02 --k1 "$k1" --focal-prior-error "$e" \
    --out "$dir/prior" >/dev/null
  "$PGBA" synth --scenario "$2" --seed "$3" --outliers 0.02 --k1 "$k1" --out "$dir/true" >/dev/null
  cp "$dir/true/gt/cameras.txt" "$dir/true/input/cameras.txt"  # synth's input holds k = 0: give it the lens
  bench "$dir/true/input" "$dir/prior/gt" "$out/calibrated.json" "$dir/calibrated"
  bench "$dir/prior/input" "$dir/prior/gt" "$out/self_calibration.json" "$dir/selfcal"
  if [[ $converged == 1 ]]; then bench "$dir/prior/input" "$dir/prior/gt" "$out/converged.json" "$dir/converged"; fi
  ln -sfn prior/gt "$dir/gt"
}
rendered_scene() {  # DIR SEED
  local dir=$1 config=()
  [[ -n ${CONFIG:-} ]] && config=(--config "$CONFIG")
  "$PGBA" synth --render --seed "$2" --k1 "$k1" --focal-prior-error "$e" --out "$dir/scene" >/dev/null
  "$PGBA" run "${config[@]}" --images "$dir/scene/images" --calib "$dir/scene/gt/cameras.txt" --out "$dir/run_true" \
    >"$dir/run_true.log" 2>&1
  mkdir -p "$dir/run_prior"
  cp -r "$dir/run_true/features" "$dir/run_prior/"  # same photos and options: cached features
  "$PGBA" run "${config[@]}" --images "$dir/scene/images" --calib "$dir/scene/cameras.txt" --calib-prior \
    --out "$dir/run_prior" >"$dir/run_prior.log" 2>&1
  for run in run_prior run_true; do
    "$PGBA" evaluate "$dir/$run/sparse" --obs "$dir/$run/tracks" --gt "$dir/scene/gt" --json "$dir/$run/eval.json" \
      >/dev/null
  done
  bench "$dir/run_true/tracks" "$dir/scene/gt" "$out/calibrated.json" "$dir/calibrated"
  bench "$dir/run_prior/tracks" "$dir/scene/gt" "$out/rendered_tracks.json" "$dir/selfcal"
  if [[ $converged == 1 ]]; then bench "$dir/run_prior/tracks" "$dir/scene/gt" "$out/converged.json" "$dir/converged"; fi
  ln -sfn scene/gt "$dir/gt"
}

for scene in "${scenes[@]}"; do
  [[ ${TABLE_ONLY:-0} == 1 ]] && break
  IFS=: read -r kind seed <<<"$scene"
  dir=$out/${kind}_$seed
  mkdir -p "$dir"
  if [[ $kind == rendered ]]; then rendered_scene "$dir" "$seed"; else tracks_scene "$dir" "$kind" "$seed"; fi
done

python3 - "$out" "${scenes[@]}" <<'EOF' | tee "$out/table.md"
import json, math, os, sys
out, scenes = sys.argv[1], sys.argv[2:]
def first_camera(path):
    for line in open(path):
        if line.strip() and not line.startswith('#'):
            p = line.split()
            return p[1], [float(x) for x in p[4:]]
def intrinsic_errors(gt, model, params):
    gt_model, g = gt
    k1_index = {'SIMPLE_RADIAL': 3, 'RADIAL': 3, 'OPENCV': 4, 'FULL_OPENCV': 4}
    k_gt = g[k1_index[gt_model]] if gt_model in k1_index else 0.0
    k = params[k1_index[model]] if model in k1_index else float('nan')
    return 100 * (params[0] / g[0] - 1), k - k_gt
def load(path):
    try:
        return json.load(open(path))
    except (OSError, ValueError):
        return None
print("| scene | method | images | focal err % | k1 err | rel. rot err (deg) | ratio to calibrated pointless |")
print("|---|---|---|---|---|---|---|")
for scene in scenes:
    kind, seed = scene.split(':')
    d = f"{out}/{kind}_{seed}"
    gt = first_camera(f"{d}/gt/cameras.txt")
    cal = load(f"{d}/calibrated/benchmark.json")
    ref = cal["methods"]["pointless"]["rel_rot_err_deg_median"] if cal else float('nan')
    rows = []
    if cal:
        for m, name in (("pointless", "calibrated, pointless"), ("pointbased", "calibrated, point-based")):
            r = cal["methods"][m]
            rows.append((name, r, None))
    if kind == 'rendered':
        for run, name in (("run_true", "calibrated, `pgba run`"), ("run_prior", "self-cal., `pgba run` (pointless)")):
            ev = load(f"{d}/{run}/eval.json")
            if ev:
                rows.append((name, ev, first_camera(f"{d}/{run}/sparse/cameras.txt") if run == "run_prior" else None))
    for sub, label in (("selfcal", "self-cal."), ("converged", "self-cal. converged")):
        b = load(f"{d}/{sub}/benchmark.json")
        if not b:
            continue
        for m, name in (("pointless", "pointless"), ("pointbased", "point-based")):
            r = b["methods"][m]
            cam = r.get("intrinsics", [{}])[0]
            rows.append((f"{label}, {name}", r, (cam.get("model"), cam.get("final_params")) if cam else None))
    for name, r, cam in rows:
        f = k = ""
        if cam and cam[1]:
            fe, ke = intrinsic_errors(gt, cam[0], cam[1])
            f, k = f"{fe:+.3f}", f"{ke:+.4f}"
        rel = r["rel_rot_err_deg_median"]
        reg = f"{r['images_registered']}/{r['images_input']}"
        print(f"| {scene} | {name} | {reg} | {f} | {k} | {rel:.5f} | {rel / ref:.2f}x |")
EOF
