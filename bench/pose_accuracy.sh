#!/usr/bin/env bash
# Pose accuracy and time of the pointless BA against the point-based BA, scene by scene, all
# in one run: `pgba benchmark` on synthetic scenes (0.5 px noise,
# 2% gross outliers) and on the tracks of real datasets, then one row per scene:
#   rel. rotation error (median and max over all image pairs, gauge-free) pointless / point-based,
#   translation-direction error ratio, sigma ratio, unknowns ratio, and the time ratio
#   (pointless adjustment + its preparation) / (point-based adjustment + its triangulation).
#
# Usage: bench/pose_accuracy.sh OUT [SCENE...]
#   SCENE: orbit:SEED | aerial:SEED[:IMAGES] | planar:SEED | longfocal:SEED | tracks:DIR:GT
#   default: orbit, aerial, planar and longfocal at seeds 1-4.
# Environment: PGBA (default: newest build*/bin/pgba), CONFIG (a config for both methods),
#   THREADS (pgba --threads; 1 makes the cpu column the single-thread time ratio),
#   PERTURB (degrees: every initial pose rotated by this much about a random axis, centres moved
#   alike, `benchmark --perturb-deg`; relative rotations then move by about 1.4x this),
#   PERTURB_SEED (its seed, default 1).
# Columns: time = wall-clock ratio; cpu = the same ratio in CPU seconds (benchmark.json
#   cpu_seconds), which a loaded machine inflates far less than wall time.
set -euo pipefail
if [[ $# -lt 1 ]]; then
  echo "usage: $0 OUT [SCENE...]" >&2
  exit 2
fi
out=$1
shift
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/pgba_binary.sh"
scenes=("$@")
if [[ ${#scenes[@]} -eq 0 ]]; then
  for s in orbit aerial planar longfocal; do
    for seed in 1 2 3 4; do scenes+=("$s:$seed"); done
  done
fi
config_args=()
thread_args=()
[[ -n "${THREADS:-}" ]] && thread_args=(--threads "$THREADS")
[[ -n "${CONFIG:-}" ]] && config_args=(--config "$CONFIG")
perturb_args=()
[[ -n "${PERTURB:-}" ]] && perturb_args=(--perturb-deg "$PERTURB" --perturb-seed "${PERTURB_SEED:-1}")
mkdir -p "$out"

for scene in "${scenes[@]}"; do
  IFS=: read -r kind a b <<<"$scene"
  name=${scene//[:\/]/_}
  dir=$out/$name
  bench_args=()
  if [[ $kind == tracks ]]; then
    bench_args=(--tracks "$a" --gt "$b")
  else
    synth_args=(--scenario "$kind" --seed "$a" --noise 0.5 --outliers 0.02 --out "$dir/scene")
    [[ -n "$b" ]] && synth_args+=(--images "$b")
    "$PGBA" synth "${synth_args[@]}" >"$dir.synth.log" 2>&1 || { echo "$scene: synth failed"; continue; }
    bench_args=(--tracks "$dir/scene/input" --gt "$dir/scene/gt")
    [[ -f "$dir/scene/loop_pairs.txt" ]] && bench_args+=(--loop "$dir/scene/loop_pairs.txt")
  fi
  "$PGBA" "${thread_args[@]}" benchmark "${bench_args[@]}" "${config_args[@]}" "${perturb_args[@]}" --no-convergence --out "$dir/benchmark" \
    >"$dir.benchmark.log" 2>&1 || { echo "$scene: benchmark failed (see $dir.benchmark.log)"; continue; }
done

python3 - "$out" "${scenes[@]}" <<'EOF'
import json, sys
out, scenes = sys.argv[1], sys.argv[2:]
print(f"{'scene':24} {'rel_rot pl':>10} {'pb':>9} {'ratio':>6} {'max ratio':>9} {'dir ratio':>9} "
      f"{'sigma':>6} {'cost':>8} {'params':>6} {'time':>6} {'cpu':>6} {'passes':>6} {'images pl/pb':>12}")
for scene in scenes:
    name = scene.replace(':', '_').replace('/', '_')
    try:
        j = json.load(open(f"{out}/{name}/benchmark/benchmark.json"))
    except OSError:
        print(f"{scene:24} (no benchmark.json)")
        continue
    pl, pb = j["methods"]["pointless"], j["methods"]["pointbased"]
    def g(m, k):
        return m.get(k, float('nan'))
    t = lambda m: m["adjust_seconds"] + m["prepare_seconds"]
    def passes(m):
        d = m.get("details", {}).get("method", {})
        return f"{d.get('relinearizations', '?')}{'' if d.get('converged', True) else '!'}"
    cpu = pl.get("cpu_seconds", float('nan')) / pb.get("cpu_seconds", float('nan'))
    print(f"{scene[:24]:24} {g(pl,'rel_rot_err_deg_median'):10.5f} {g(pb,'rel_rot_err_deg_median'):9.5f} "
          f"{g(pl,'rel_rot_err_deg_median')/g(pb,'rel_rot_err_deg_median'):6.3f} "
          f"{g(pl,'rel_rot_err_deg_max')/g(pb,'rel_rot_err_deg_max'):9.3f} "
          f"{g(pl,'rel_dir_err_deg_median')/g(pb,'rel_dir_err_deg_median'):9.3f} "
          f"{g(pl,'sigma_final')/g(pb,'sigma_final'):6.3f} {g(pl,'robust_cost')/g(pb,'robust_cost'):8.5f} "
          f"{pl['params']/pb['params']:6.3f} {t(pl)/t(pb):6.3f} {cpu:6.3f} {passes(pl):>6} "
          f"{pl.get('images_registered','?'):>5}/{pb.get('images_registered','?')}")
EOF
