#!/usr/bin/env bash
# A thousand photos (docs/benchmarks.md): renders an aerial block (`pgba synth --render --scene
# aerial`: 1024 x 768 photos of a textured town with box buildings, strips with 75% forward
# and 50% side overlap) and runs `pgba run` on it with retrieval pairs, then prints one
# table row: images, seconds to render, seconds per stage (report.json), their sum, the wall
# time of `pgba run`, peak
# memory (maximum resident set size from /usr/bin/time -v), the matched pairs against the
# n x neighbors bound and their recall of the pairs whose true footprints overlap >= 50%
# (DIR/overlap.txt), registered images, rotation errors against the truth (median, max),
# and the load average sampled every 20 s during the run (the machine may be shared).
#
# Usage: bench/thousand_photos.sh OUT [IMAGES]   (IMAGES default 1000)
# Environment: PGBA=path/to/pgba (default: newest build*/bin/pgba), CONFIG (default
#   configs/aerial_large.json), SEED (1), SYNTH_ARGS (extra `pgba synth` arguments). A scene
#   already rendered in OUT/scene with the same arguments is reused (OUT/scene/synth_args).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
[[ $# -ge 1 && $# -le 2 ]] || { echo "usage: $0 OUT [IMAGES]" >&2; exit 2; }
out=$1
images=${2:-1000}
[[ "$images" =~ ^[0-9]+$ && "$images" -ge 4 ]] || { echo "error: IMAGES must be an integer >= 4, got '$images'" >&2; exit 2; }
source "$here/bench/pgba_binary.sh"
config=${CONFIG:-$here/configs/aerial_large.json}
[[ -f "$config" ]] || { echo "error: config '$config' not found" >&2; exit 2; }
[[ -x /usr/bin/time ]] || { echo "error: /usr/bin/time not found (apt-get install time)" >&2; exit 2; }
mkdir -p "$out"

synth_args="--render --scene aerial --images $images --seed ${SEED:-1} ${SYNTH_ARGS:-}"
render_s=reused
if [[ ! -f "$out/scene/synth_args" || "$(cat "$out/scene/synth_args")" != "$synth_args" ]]; then
  rm -rf "$out/scene"
  # shellcheck disable=SC2086
  /usr/bin/time -v "$PGBA" synth $synth_args --out "$out/scene" >"$out/synth.log" 2>&1 ||
    { echo "error: pgba synth failed, see $out/synth.log" >&2; exit 1; }
  render_s=$(awk -F': ' '/Elapsed \(wall clock\)/ {
    n = split($2, t, ":"); s = 0; for (i = 1; i <= n; i++) s = 60 * s + t[i]; print s }' "$out/synth.log")
  echo "$synth_args" >"$out/scene/synth_args"
fi

rm -rf "$out/run"
: >"$out/load.txt"
(while true; do cut -d' ' -f1 /proc/loadavg >>"$out/load.txt"; sleep 20; done) &
sampler=$!
trap 'kill $sampler 2>/dev/null || true' EXIT
status=0
/usr/bin/time -v "$PGBA" run --images "$out/scene/images" --calib "$out/scene/cameras.txt" --gt "$out/scene/gt" \
  --config "$config" --out "$out/run" >"$out/run.log" 2>&1 || status=$?
kill $sampler 2>/dev/null || true
[[ $status -eq 0 ]] || echo "warning: pgba run exited with $status, see $out/run.log" >&2

python3 - "$out" "$render_s" "$config" <<'PY'
import json, sys
out, render_s, config = sys.argv[1:4]
def timed(key):
    for line in open(f"{out}/run.log"):
        if key in line:
            return line.rsplit(": ", 1)[1].strip()
    return "0"
peak_gib = int(timed("Maximum resident set size")) / 2**20
wall = 0.0
for part in timed("Elapsed (wall clock)").split(":"):
    wall = 60 * wall + float(part)
rep = json.load(open(f"{out}/run/report.json")) if __import__("os").path.exists(f"{out}/run/report.json") else {}
st = {k: v.get("seconds", 0.0) for k, v in rep.get("stages", {}).items() if isinstance(v, dict)}
ev = rep.get("evaluation", {})
cfg = json.load(open(config))
k = cfg.get("matching", {}).get("pairs", {}).get("vlad", {}).get("neighbors", 20)
selected = set()
try:
    for line in open(f"{out}/run/matching/pairs.txt"):
        if line.startswith("#") or not line.strip(): continue
        a, b = line.split()[:2]
        selected.add((min(a, b), max(a, b)))
except FileNotFoundError:
    pass
truth = set()
for line in open(f"{out}/scene/overlap.txt"):
    a, b, v = line.split()
    if float(v) >= 0.5: truth.add((min(a, b), max(a, b)))
n = len(__import__("os").listdir(f"{out}/scene/images"))
load = [float(x) for x in open(f"{out}/load.txt") if x.strip()]
stages = ["features", "match", "pairs", "triplets", "global_init", "local_hessians", "global_ba", "triangulation"]
print("images | render s | " + " | ".join(f"{s} s" for s in stages) + " | other s | stages s | wall s | peak RSS GiB | pairs "
      "(<= n k) | recall of >=50% overlaps | registered | rot err median deg | rot err max deg | load avg mean (max)")
print("|".join(["---"] * (len(stages) + 13)))
total = sum(st.values())
other = total - sum(st.get(s, 0.0) for s in stages)
print(f"{n} | {render_s} | " + " | ".join(f"{st.get(s, 0.0):.1f}" for s in stages) +
      f" | {other:.1f} | {total:.1f} | {wall:.1f} | {peak_gib:.2f} | {len(selected)} (<= {n * k}) | "
      f"{len(truth & selected) / max(1, len(truth)):.3f} of {len(truth)} | {ev.get('images_registered', 0)}/{n} | "
      f"{ev.get('rot_err_deg_median', float('nan')):.4f} | {ev.get('rot_err_deg_max', float('nan')):.4f} | "
      f"{sum(load) / max(1, len(load)):.2f} ({max(load, default=0):.2f})")
PY
