#!/usr/bin/env bash
# Self-calibration from a wrong PINHOLE prior on temple_sparse_ring, over several prior errors:
# where fx and fy end, their standard deviations from the global BA, the rotation errors.
# With fx and fy apart (intrinsics.refine_aspect_ratio true, e.g. CONFIG=cfg.json) fx is not
# observable on this ring and its result depends on the solver's path.
#
# Usage: bench/temple_prior_survey.sh OUT [FACTOR...]   (default factors 1.08 1.09 1.10 1.11 1.12)
# Environment: PGBA (default: build/bin/pgba), SHARED (default: ../shared beside the repository),
#   CONFIG (a config file for every run, default none).
set -euo pipefail
[[ $# -ge 1 ]] || { echo "usage: $0 OUT [FACTOR...]" >&2; exit 2; }
out=$1
shift
factors=("$@")
[[ ${#factors[@]} -eq 0 ]] && factors=(1.08 1.09 1.10 1.11 1.12)
here=$(cd "$(dirname "$0")/.." && pwd)
pgba=${PGBA:-$here/build/bin/pgba}
data=${SHARED:-$here/../shared}/datasets/temple_sparse_ring
[[ -x $pgba && -d $data/images ]] || { echo "error: $pgba or $data missing" >&2; exit 2; }
mkdir -p "$out/photos/images"
for f in "$data"/images/*; do ln -sf "$f" "$out/photos/images/"; done  # no cameras.txt beside them
config=()
[[ -n ${CONFIG:-} ]] && config=(--config "$CONFIG")
"$pgba" -v 0 run "${config[@]}" --images "$out/photos/images" --calib "$data/cameras.txt" --gt "$data/gt" --out "$out/calibrated" \
  >"$out/calibrated.log" 2>&1
read -r fx fy cx cy < <(awk '!/^#/ && NF {print $5, $6, $7, $8; exit}' "$data/cameras.txt")
for f in "${factors[@]}"; do
  python3 -c "print('1 PINHOLE 640 480 %.6g %.6g $cx $cy' % ($f * $fx, $f * $fy))" >"$out/prior_$f.txt"
  rm -rf "$out/run_$f" && mkdir -p "$out/run_$f" && cp -r "$out/calibrated/features" "$out/run_$f/"
  "$pgba" -v 0 run "${config[@]}" --images "$out/photos/images" --calib "$out/prior_$f.txt" --calib-prior --gt "$data/gt" \
    --out "$out/run_$f" >"$out/run_$f.log" 2>&1 || { echo "$f: run failed (see $out/run_$f.log)"; continue; }
  python3 - "$out/run_$f/report.json" "$f" "$fx" "$fy" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); e = r["evaluation"]; cam = r["intrinsics"][0]
fx, fy = float(sys.argv[3]), float(sys.argv[4])
efx, efy = cam["final_params"][0], cam["final_params"][1]
sd = ", ".join(f"{p['name']} sd " + ("n/a" if p["stddev"] is None else f"{p['stddev']:.1f}") for p in cam["params"])
print(f"prior x{sys.argv[2]}: {e['images_registered']} registered, sigma rms {e['sigma_rms']:.4f} px, "
      f"rot err {e['rot_err_deg_median']:.3f} deg "
      f"(rel {e['rel_rot_err_deg_median']:.3f}), fx {efx:.1f}, fy {efy:.1f} ({sd}), mean focal error "
      f"{100 * ((efx + efy) / (fx + fy) - 1):+.2f}%")
PY
done
