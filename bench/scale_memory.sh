#!/usr/bin/env bash
# Memory and time of `pgba reconstruct` as the aerial block grows: for each size a synthetic
# aerial block (seed 3, 0.5 px noise, 2% gross outliers), reconstructed with configs/aerial.json
# under /usr/bin/time -v, the resident memory also sampled from outside every 0.2 s. One row per
# size: images, observations, each stage's own peak resident memory (report.json
# stages.NAME.peak_rss_mb; MB = MiB), the process' peak (report.json peak_rss_mb and the outside
# sample's maximum), wall and CPU seconds of tracks -> poses (every stage from the tracks read to
# the final poses and points, the workspace writes excluded) and of the whole command, whether
# the global BA converged, and the median rotation error against the truth (pgba evaluate,
# gauge-free relative rotations).
#
# Usage: bench/scale_memory.sh OUT [IMAGES...]     (default sizes: 1000 3000 10000)
# Environment: PGBA (default: newest build*/bin/pgba), THREADS (pgba --threads, default 2),
#   CONFIG (default configs/aerial.json), SEED (default 3). Scenes already in OUT are reused.
set -euo pipefail
if [[ $# -lt 1 ]]; then
  echo "usage: $0 OUT [IMAGES...]" >&2
  exit 2
fi
out=$1
shift
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/pgba_binary.sh"
sizes=("$@")
[[ ${#sizes[@]} -eq 0 ]] && sizes=(1000 3000 10000)
threads=${THREADS:-2}
config=${CONFIG:-$here/configs/aerial.json}
seed=${SEED:-3}
mkdir -p "$out"

# Largest VmRSS (kB) of process $1 while it lives, sampled every 0.2 s, written to $2.
sample_rss() {
  local pid=$1 file=$2 max=0 kb
  while kill -0 "$pid" 2>/dev/null; do
    kb=$(awk '/^VmRSS:/ {print $2}' "/proc/$pid/status" 2>/dev/null || echo 0)
    [[ -n "$kb" && "$kb" -gt "$max" ]] && max=$kb
    sleep 0.2
  done
  echo "$max" >"$file"
}

for n in "${sizes[@]}"; do
  scene=$out/aerial$n
  if [[ ! -f $scene/input/images.txt ]]; then
    "$PGBA" synth --scenario aerial --seed "$seed" --noise 0.5 --outliers 0.02 --images "$n" --out "$scene" \
      >"$out/synth$n.log" 2>&1 || { echo "$n: synth failed (see $out/synth$n.log)"; continue; }
  fi
  run=$out/run$n
  rm -rf "$run"
  /usr/bin/time -v "$PGBA" --threads "$threads" reconstruct --tracks "$scene/input" --config "$config" --out "$run" \
    >"$out/run$n.log" 2>"$out/run$n.time" &
  pid=$!
  # /usr/bin/time's child: the pgba process itself.
  sleep 0.5
  child=$(pgrep -P "$pid" | head -1 || true)
  [[ -n "$child" ]] && sample_rss "$child" "$out/run$n.rss" &
  sampler=$!
  status=0
  wait "$pid" || status=$?
  wait "$sampler" 2>/dev/null || true
  [[ $status -eq 0 ]] || { echo "$n: reconstruct failed (see $out/run$n.log)"; continue; }
  "$PGBA" evaluate "$run/sparse" --obs "$scene/input" --gt "$scene/gt" --json "$run/evaluation.json" \
    >"$out/evaluate$n.log" 2>&1 || echo "$n: evaluate failed (see $out/evaluate$n.log)"
done

python3 - "$out" "${sizes[@]}" <<'EOF'
import json, os, re, sys
out, sizes = sys.argv[1], sys.argv[2:]
stages = ["input", "pairs", "triplets", "global_init", "local_hessians", "local_hessians_output", "global_ba",
          "verification", "triangulation", "output"]
short = {"input": "input", "pairs": "pairs", "triplets": "tripl", "global_init": "init",
         "local_hessians": "lhess", "local_hessians_output": "lhwrite", "global_ba": "gba", "verification": "verif", "triangulation": "triang",
         "output": "write"}
head = ["images", "observations"] + [short[s] + "_MB" for s in stages] + \
       ["peak_MB", "sampled_MB", "poses_wall_s", "poses_cpu_s", "total_wall_s", "total_cpu_s", "converged",
        "passes", "rot_err_med_deg", "rel_rot_med_deg"]
print("per-stage peak resident memory (MB) and times; poses_* = tracks -> poses (every stage but the write)")
print(" ".join(head))
for n in sizes:
    run = os.path.join(out, "run" + n)
    try:
        r = json.load(open(os.path.join(run, "report.json")))
    except OSError:
        print(n, "- (no report)")
        continue
    st = r["stages"]
    row = [str(r.get("images_registered", "-")) + "/" + str(r.get("images_input", n)),
           str(st.get("input", {}).get("observations", "-"))]
    for s in stages:
        row.append("%.0f" % st[s]["peak_rss_mb"] if s in st else "-")
    row.append("%.0f" % r.get("peak_rss_mb", float("nan")))
    try:
        row.append("%.0f" % (int(open(os.path.join(out, "run" + n + ".rss")).read()) / 1024))
    except (OSError, ValueError):
        row.append("-")
    poses = [s for s in st if s not in ("output", "local_hessians_output")]
    row.append("%.1f" % sum(st[s]["seconds"] for s in poses))
    row.append("%.1f" % sum(st[s].get("cpu_seconds", 0) for s in poses))
    t = open(os.path.join(out, "run" + n + ".time")).read()
    def field(name):
        m = re.search(name + r".*?: ([0-9:.]+)", t)
        return m.group(1) if m else "0"
    wall = field("Elapsed \\(wall clock\\) time")
    parts = [float(p) for p in wall.split(":")]
    seconds = sum(p * 60 ** (len(parts) - 1 - i) for i, p in enumerate(parts))
    row.append("%.1f" % seconds)
    row.append("%.1f" % (float(field("User time")) + float(field("System time"))))
    g = st.get("global_ba", {})
    row.append(str(g.get("converged", "-")).lower())
    row.append(str(len(g.get("passes", []))))
    try:
        e = json.load(open(os.path.join(run, "evaluation.json")))
        row.append("%.4f" % e["rot_err_deg_median"])
        row.append("%.4f" % e["rel_rot_err_deg_median"])
    except (OSError, KeyError):
        row += ["-", "-"]
    print(" ".join(row))
EOF
