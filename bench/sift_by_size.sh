#!/usr/bin/env bash
# pgba's SIFT against OpenCV's through the whole pipeline at several detection sizes (where
# `features.sift.implementation` "auto" switches to pgba's). For each dataset and each
# `features.sift.max_image_size` of SIZES (only those below the images' larger side, plus
# the native size), `pgba run --gt` from scratch once with "opencv" and once with "pgba"
# (alternated: opencv first at one size, pgba first at the next, so a load drift hits both
# alike), then per run: detection megapixels, features per image, verified pairs and
# matches, tracks, registered images, the Sim(3)-aligned rotation error and the gauge-free
# relative rotation error (`pgba evaluate --obs RUN/tracks --gt GT --json`), median / max,
# the features stage's CPU s per image, and the two implementations' poses against each
# other (`pgba evaluate PGBA_RUN/sparse --gt OPENCV_RUN/sparse`): how far the features
# alone move the result.
#
# Usage: bench/sift_by_size.sh DATASET_DIR[:CONFIG] ...
#   CONFIG: a JSON config or preset the run starts from (e.g. configs/object_ring.json for
#   the Middlebury rings); the implementation and max_image_size are set on top of it.
# Environment: PGBA (default: newest build*/bin/pgba), SIZES (default "640 1024 1400 1728
#   2160 3072": 0.27 / 0.70 / 1.31 / 1.99 / 3.11 / 6.29 MP on a 3072 x 2048 photo),
#   KEEP=DIR keeps the runs there (default: a temporary folder, removed); a re-run with the same
#   KEEP skips the runs already there (and so only prints the table once all are done).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/lib.sh"
if [[ $# -eq 0 ]]; then echo "usage: $0 DATASET_DIR[:CONFIG] ..." >&2; exit 2; fi
read -r -a sizes <<<"${SIZES:-640 1024 1400 1728 2160 3072}"
if [[ -n "${KEEP:-}" ]]; then tmp=$KEEP; mkdir -p "$tmp"; else tmp=$(mktemp -d /tmp/pgba_sift_size_XXXX); trap 'rm -rf "$tmp"' EXIT; fi

run_one() {  # DATASET CONFIG IMPL SIZE: one run and its evaluation into $tmp/NAME_SIZE_IMPL
  local ds=$1 base=$2 impl=$3 size=$4 out
  out="$tmp/$(basename "$ds")_${size}_$impl"
  [[ -n "${KEEP:-}" && -f "$out/report.json" && -f "$out.load" ]] && return  # done in an earlier run of KEEP
  python3 - "$base" "$impl" "$size" >"$out.json" <<'PY'
import json, sys
cfg = json.load(open(sys.argv[1])) if sys.argv[1] else {}
sift = cfg.setdefault("features", {}).setdefault("sift", {})
sift["implementation"], sift["max_image_size"] = sys.argv[2], int(sys.argv[3])
print(json.dumps(cfg))
PY
  rm -rf "$out"
  "$PGBA" -v 0 run --images "$ds/images" --calib "$ds/cameras.txt" --gt "$ds/gt" --config "$out.json" --out "$out" \
    >"$out.log" 2>&1 || echo "warning: $impl at $size on $(basename "$ds") failed: $(grep -m1 error "$out.log")" >&2
  if [[ -d "$out/sparse" ]]; then
    "$PGBA" -v 0 evaluate "$out/sparse" --obs "$out/tracks" --gt "$ds/gt" --json "$out.eval.json" >/dev/null 2>&1 || true
  fi
  cut -d' ' -f1 /proc/loadavg >"$out.load"
}

rows=()
for arg in "$@"; do
  ds=${arg%%:*} config=""
  [[ $arg == *:* ]] && config=${arg#*:}
  [[ -d "$ds/images" && -f "$ds/cameras.txt" && -d "$ds/gt" ]] || { echo "error: $ds: needs images/, cameras.txt, gt/" >&2; exit 2; }
  [[ -z "$config" || -f "$config" ]] || { echo "error: $config: no such config" >&2; exit 2; }
  # The images' larger side, from the calibration (COLMAP cameras.txt: ID MODEL WIDTH HEIGHT ...).
  side=$(grep -v '^#' "$ds/cameras.txt" | awk 'NF {print ($3 > $4 ? $3 : $4); exit}')
  used=()
  for s in "${sizes[@]}"; do ((s < side)) && used+=("$s"); done
  used+=("$side")
  flip=0
  for s in "${used[@]}"; do
    if ((flip)); then order=(pgba opencv); else order=(opencv pgba); fi
    flip=$((1 - flip))
    for impl in "${order[@]}"; do run_one "$ds" "$config" "$impl" "$s"; done
    a="$tmp/$(basename "$ds")_${s}_opencv" b="$tmp/$(basename "$ds")_${s}_pgba"
    if [[ -d "$a/sparse" && -d "$b/sparse" ]]; then
      "$PGBA" -v 0 evaluate "$b/sparse" --obs "$b/tracks" --gt "$a/sparse" --json "$b.cross.json" >/dev/null 2>&1 || true
    fi
    rows+=("$(basename "$ds") $s $side")
  done
done

echo "pgba run --gt per detection size, opencv vs pgba SIFT, $(nproc) cores, load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
python3 - "$tmp" "${rows[@]}" <<'PY'
import json, os, sys
tmp, rows = sys.argv[1], sys.argv[2:]
nan = float("nan")
def load(p):
    try:
        return json.load(open(p))
    except (OSError, ValueError):
        return {}
print("dataset | max_image_size | MP | SIFT | features/image | verified pairs | verified matches | tracks | registered "
      "| rot err median | rot err max | rel rot err median | rel rot err max | pgba vs opencv poses: rot median / max "
      "| CPU s/image features | load after")
print("|".join(["---"] * 16))
for row in rows:
    name, size, side = row.split()
    for impl in ("opencv", "pgba"):
        run = f"{tmp}/{name}_{size}_{impl}"
        rep, ev = load(f"{run}/report.json"), load(f"{run}.eval.json")
        ev = ev.get("evaluation", ev)
        st = rep.get("stages", {})
        f, m = st.get("features", {}), st.get("match", {})
        n = f.get("images", 0) or 1
        # Detection megapixels: the full images' scaled by max_image_size.
        mp = f.get("megapixels_extracted", nan) / n * min(1.0, int(size) / int(side)) ** 2
        cross = ""
        if impl == "pgba":
            c = load(f"{run}.cross.json")
            c = c.get("evaluation", c)
            cross = f"{c.get('rot_err_deg_median', nan):.4f} / {c.get('rot_err_deg_max', nan):.4f}"
        reg = ev.get("images_registered", rep.get("evaluation", {}).get("images_registered", 0))
        if rep.get("status") != "ok":
            reg = f"0 ({str(rep.get('error', 'failed'))[:50]})"
        print(f"{name} | {size} | {mp:.2f} | {impl} | {f.get('features_mean', nan):.0f} | "
              f"{m.get('pairs_verified', '?')}/{m.get('pairs', '?')} | {m.get('verified_matches', '?')} | "
              f"{m.get('tracks', '?')} | {reg}/{f.get('images', '?')} | "
              f"{ev.get('rot_err_deg_median', nan):.4f} | {ev.get('rot_err_deg_max', nan):.4f} | "
              f"{ev.get('rel_rot_err_deg_median', nan):.4f} | {ev.get('rel_rot_err_deg_max', nan):.4f} | {cross} | "
              f"{f.get('cpu_seconds', nan) / n:.2f} | {open(run + '.load').read().strip()}")
PY
