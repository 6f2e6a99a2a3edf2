#!/usr/bin/env bash
# Self-calibration from a wrong PINHOLE prior on temple_sparse_ring with the tracks held
# (fx is not observable on this ring, bench/temple_prior_survey.sh): the calibrated run's tracks handed the prior camera, `pgba benchmark`
# with every camera's intrinsics free, so that only the adjustments differ (no second matching
# pass as in bench/temple_prior_survey.sh). One row per prior and method (pointless and
# point-based, the same unknowns): the fraction of the tracks' observations within 4 px of the
# method's model (its inliers), sigma, the rotation errors (Sim3 median, gauge-free relative
# median) and the focal error.
#
# Usage: bench/temple_fixed_tracks.sh OUT [FACTOR...]   (default factors 1.08 1.10 1.12 0.92)
# Environment: PGBA (default: build/bin/pgba), SHARED (default: ../shared beside the repository),
#   CONFIG (a JSON object merged into every benchmark's config, e.g. '{"global_ba": {...}}'),
#   TAG (default "run": the benchmarks go to OUT/TAG_FACTOR, so variants share OUT/calibrated).
set -euo pipefail
[[ $# -ge 1 ]] || { echo "usage: $0 OUT [FACTOR...]" >&2; exit 2; }
out=$1
shift
factors=("$@")
[[ ${#factors[@]} -eq 0 ]] && factors=(1.08 1.10 1.12 0.92)
here=$(cd "$(dirname "$0")/.." && pwd)
pgba=${PGBA:-$here/build/bin/pgba}
data=${SHARED:-$here/../shared}/datasets/temple_sparse_ring
tag=${TAG:-run}
[[ -x $pgba && -d $data/images ]] || { echo "error: $pgba or $data missing" >&2; exit 2; }
mkdir -p "$out/photos/images"
for f in "$data"/images/*; do ln -sf "$f" "$out/photos/images/"; done
if [[ ! -f $out/calibrated/tracks/images.txt ]]; then
  "$pgba" -v 0 run --images "$out/photos/images" --calib "$data/cameras.txt" --gt "$data/gt" --out "$out/calibrated" \
    >"$out/calibrated.log" 2>&1
fi
read -r fx fy cx cy < <(awk '!/^#/ && NF {print $5, $6, $7, $8; exit}' "$data/cameras.txt")
python3 - "$out/$tag.json" "${CONFIG:-{\}}" <<'PY'
import json, sys
config = {"intrinsics": {"cameras": "all"}}
def merge(a, b):
    for k, v in b.items():
        a[k] = merge(a.get(k, {}), v) if isinstance(v, dict) else v
    return a
json.dump(merge(config, json.loads(sys.argv[2])), open(sys.argv[1], "w"))
PY
for f in "${factors[@]}"; do
  tracks=$out/tracks_$f
  rm -rf "$tracks" && cp -r "$out/calibrated/tracks" "$tracks"
  awk -v f="$f" '/^#/ || !NF {print; next} {$5 = sprintf("%.6g", f * $5); $6 = sprintf("%.6g", f * $6); print}' \
    "$out/calibrated/tracks/cameras.txt" >"$tracks/cameras.txt"
  rm -rf "$out/${tag}_$f"
  "$pgba" -v 1 benchmark --tracks "$tracks" --gt "$data/gt" --config "$out/$tag.json" --no-convergence \
    --out "$out/${tag}_$f" >"$out/${tag}_$f.log" 2>&1 || { echo "$f: benchmark failed (see $out/${tag}_$f.log)"; continue; }
  python3 - "$out/${tag}_$f/benchmark.json" "$f" "$fx" "$fy" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
fx, fy = float(sys.argv[3]), float(sys.argv[4])
for name in ("pointless", "pointbased"):
    m = r["methods"][name]
    p = m["intrinsics"][0]["final_params"]
    inl = m.get("inlier_fraction", float("nan"))
    print(f"x{sys.argv[2]} {name:10s}: inliers {inl:.4f}, sigma {m['sigma_final']:.4f} px, Sim3 {m['rot_err_deg_median']:.3f}"
          f" / rel {m['rel_rot_err_deg_median']:.3f} deg, focal {100 * ((p[0] + p[1]) / (fx + fy) - 1):+.2f}%, "
          f"cpu {m.get('cpu_seconds', float('nan')):.2f} s")
PY
done
