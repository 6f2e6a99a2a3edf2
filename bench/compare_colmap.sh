#!/usr/bin/env bash
# End to end, COLMAP vs pgba, on the same images, the same intrinsics and the same machine:
#   COLMAP: feature_extractor + exhaustive_matcher + mapper (CPU, incremental SfM)
#   pgba:   pgba run (features, matching, triplets, averaging, local hessians, pointless BA)
# Both largest models are judged by `pgba evaluate` against the dataset's ground truth
# (rotation and centre errors after a similarity alignment, the gauge-free median relative
# rotation error over all pairs, sigma on pgba's tracks); the images registered are counted
# over every model either writes (`reg`; `models`: how many). Prints one table with the
# wall time per stage and the focal of the result against the dataset's calibration.
#
# Two modes:
#   calibrated (default): both given the dataset's intrinsics, held (COLMAP's mapper with
#     ba_refine_* 0).
#   UNCALIBRATED=1: neither gets a calibration. COLMAP: SIMPLE_RADIAL on its own prior (no EXIF
#     in the Strecha/Middlebury files: 1.2 max(w, h)), mapper with its default refinement
#     (focal and k, principal point held). pgba: `pgba run` without --calib on links to the
#     images in a folder of its own (no cameras.txt beside them; default intrinsics "auto").
#
# Usage: bench/compare_colmap.sh [DATASET_DIR ...]   (default: every shared dataset with gt/)
#   DATASET_DIR has images/, cameras.txt and gt/ (shared/datasets/README.md).
# Environment: PGBA=path/to/pgba (default: build/bin/pgba), COLMAP=colmap, KEEP=1 keeps the
#   workspaces, CONFIG=configs/X.json passed to pgba run, UNCALIBRATED=1 (above).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
shared=$(cd "$here/.." && pwd)/shared
PGBA=${PGBA:-$here/build/bin/pgba}
source "$here/bench/lib.sh"
if [[ $# -eq 0 ]]; then
  for d in "$shared"/datasets/*/; do [[ -d "$d/gt" ]] && set -- "$@" "${d%/}"; done
fi
cfg=()
[[ -n "${CONFIG:-}" ]] && cfg=(--config "$CONFIG")
uncal=${UNCALIBRATED:-0}

printf "%-20s %-7s %8s %8s %8s %8s %6s %6s %10s %10s %11s %10s %8s %8s\n" dataset method feat_s match_s sfm_s total_s reg \
  models rot_med rot_max centre_med rel_rot_med sigma focal_%
for ds in "$@"; do
  name=$(basename "$ds")
  [[ -d "$ds/images" && -f "$ds/cameras.txt" && -d "$ds/gt" ]] || { echo "error: $ds: needs images/, cameras.txt, gt/" >&2; exit 2; }
  tmp=$(mktemp -d "/tmp/pgba_vs_colmap_${name}_XXXX")
  t0=$(now)
  if [[ $uncal == 1 ]]; then
    colmap_feature_extractor "$ds" "$tmp/colmap.db" "$tmp/colmap.log" uncalibrated
    refine=()  # COLMAP's defaults: focal and extra parameters refined, principal point held
  else
    colmap_feature_extractor "$ds" "$tmp/colmap.db" "$tmp/colmap.log"
    refine=(--Mapper.ba_refine_focal_length 0 --Mapper.ba_refine_principal_point 0 --Mapper.ba_refine_extra_params 0)
  fi
  t1=$(now)
  colmap_exhaustive_matcher "$tmp/colmap.db" "$tmp/colmap.log"
  t2=$(now)
  mkdir -p "$tmp/colmap_sparse"
  "$COLMAP" mapper --database_path "$tmp/colmap.db" --image_path "$ds/images" --output_path "$tmp/colmap_sparse" \
    "${refine[@]}" >>"$tmp/colmap.log" 2>&1 || true
  t3=$(now)
  # The largest model COLMAP produced (it may split the scene), as text; the images of every
  # model counted.
  best=""
  bestn=0
  alln=0
  models=0
  for m in "$tmp"/colmap_sparse/*/; do
    [[ -f "$m/images.bin" ]] || continue
    mkdir -p "$tmp/colmap_txt/$(basename "$m")"
    "$COLMAP" model_converter --input_path "$m" --output_path "$tmp/colmap_txt/$(basename "$m")" --output_type TXT \
      >>"$tmp/colmap.log" 2>&1
    # Two lines per image (its pose, its observations, possibly empty).
    n=$(grep -v '^#' "$tmp/colmap_txt/$(basename "$m")/images.txt" | awk 'NR % 2 == 1 && NF' | wc -l)
    alln=$((alln + n))
    models=$((models + 1))
    if (( n > bestn )); then bestn=$n; best="$tmp/colmap_txt/$(basename "$m")"; fi
  done

  if [[ $uncal == 1 ]]; then  # the photos without the cameras.txt that `pgba run` finds beside them
    mkdir -p "$tmp/photos/images"
    for f in "$ds"/images/*; do ln -s "$(cd "$(dirname "$f")" && pwd)/$(basename "$f")" "$tmp/photos/images/"; done
    calib=()
    images=$tmp/photos/images
  else
    calib=(--calib "$ds/cameras.txt")
    images=$ds/images
  fi
  t4=$(now)
  "$PGBA" -v 0 run --images "$images" "${calib[@]}" --out "$tmp/pgba" "${cfg[@]}" >"$tmp/pgba.log" 2>&1 || true
  t5=$(now)

  # Both judged on pgba's tracks (its observation model) and the ground truth.
  eval_json() {  # MODEL OUT.json
    if [[ -n "$1" && -d "$1" && -f "$tmp/pgba/tracks/points3D.txt" ]]; then
      "$PGBA" -v 0 evaluate "$1" --obs "$tmp/pgba/tracks" --gt "$ds/gt" --json "$2" >/dev/null 2>&1 || echo '{}' >"$2"
    else
      echo '{}' >"$2"
    fi
  }
  eval_json "$best" "$tmp/colmap_eval.json"
  eval_json "$tmp/pgba/sparse" "$tmp/pgba_eval.json"
  python3 - "$name" "$tmp" "$(elapsed "$t0" "$t1")" "$(elapsed "$t1" "$t2")" "$(elapsed "$t2" "$t3")" "$(elapsed "$t4" "$t5")" \
    "$(ls "$ds/images" | wc -l)" "$ds/cameras.txt" "$best" "$alln" "$models" <<'PY'
import json, os, sys
name, tmp, cf, cm, cs, pt, n = sys.argv[1], sys.argv[2], *map(float, sys.argv[3:7]), int(sys.argv[7])
calib, colmap_model, colmap_all, colmap_models = sys.argv[8], sys.argv[9], int(sys.argv[10]), int(sys.argv[11])
def mean_focal(path):  # first camera of a COLMAP cameras.txt: f, or (fx + fy) / 2
    for line in open(path):
        p = line.split()
        if p and not p[0].startswith('#'):
            two = p[1] in ('PINHOLE', 'OPENCV', 'FULL_OPENCV', 'OPENCV_FISHEYE')
            return (float(p[4]) + float(p[5])) / 2 if two else float(p[4])
def focal_err(model_dir):
    path = os.path.join(model_dir, "cameras.txt") if model_dir else ""
    return "%+.3f" % (100 * (mean_focal(path) / mean_focal(calib) - 1)) if os.path.isfile(path) else "n/a"
def row(method, f, m, s, total, e, model_dir, registered, models):
    g = lambda k, fmt: (fmt % e[k]) if k in e else "n/a"
    reg = f"{registered}/{n}"
    print(f"{name:<20} {method:<7} {f:8.1f} {m:8.1f} {s:8.1f} {total:8.1f} {reg:>6} {models:>6} {g('rot_err_deg_median', '%.4f'):>10}"
          f" {g('rot_err_deg_max', '%.4f'):>10} {g('center_err_rel_median', '%.2e'):>11}"
          f" {g('rel_rot_err_deg_median', '%.4f'):>10} {g('sigma_rms', '%.3f'):>8} {focal_err(model_dir):>8}")
row("colmap", cf, cm, cs, cf + cm + cs, json.load(open(f"{tmp}/colmap_eval.json")), colmap_model, colmap_all,
    colmap_models)
try:
    report = json.load(open(f"{tmp}/pgba/report.json"))
except Exception:
    report = {}
st = report.get("stages", {})
f = st.get("features", {}).get("seconds", 0.0)
m = st.get("match", {}).get("seconds", 0.0)
row("pgba", f, m, pt - f - m, pt, json.load(open(f"{tmp}/pgba_eval.json")), f"{tmp}/pgba/sparse",
    report.get("images_registered", 0), len(report.get("models", [])))
PY
  [[ -n "${KEEP:-}" ]] && echo "  (kept $tmp)" || rm -rf "$tmp"
done
