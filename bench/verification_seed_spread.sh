#!/usr/bin/env bash
# How far the final rotation errors move with the set of tracks alone: `pgba run --gt` with the
# front end's verification RANSAC seeded 0..SEEDS-1 (matching.verification.relative_pose.seed),
# for the OpenGV-scored verification (RANSAC, 2 fixed refinement passes; variant "opengv") and
# the Sampson-scored one (up to 6 passes until converged; variant "sampson", the default), on the same cached features. Every other option
# is the default (configs/object_ring.json on the *_ring datasets). Per dataset and variant:
# verified matches, tracks, and the median / max rotation error against the ground truth per
# seed, then their spread over the seeds; the gauge-free pairwise rotation error of the final
# model; and the minimum over the seeds of the matching time per pair (the variants alternate,
# so a shared machine's load falls on both alike). One build, so the two variants run the same
# code everywhere but the verification's scoring and refinement. KEEP_DIR=DIR keeps the runs
# (and a re-run skips those already done).
#
# Usage: bench/verification_seed_spread.sh PGBA SEEDS [DATASET_DIR ...]
#   (default datasets: fountain_p11 herzjesu_p8 entry_p10 temple_sparse_ring of ../shared/datasets)
set -euo pipefail
if [[ $# -lt 2 ]]; then echo "usage: $0 PGBA SEEDS [DATASET_DIR ...]" >&2; exit 2; fi
bin=$1 seeds=$2
shift 2
here=$(cd "$(dirname "$0")/.." && pwd)
shared=$(cd "$here/.." && pwd)/shared
if [[ $# -eq 0 ]]; then
  set -- "$shared/datasets/fountain_p11" "$shared/datasets/herzjesu_p8" "$shared/datasets/entry_p10" \
    "$shared/datasets/temple_sparse_ring"
fi
[[ -x "$bin" ]] || { echo "error: $bin is not an executable" >&2; exit 2; }
tmp=${KEEP_DIR:-$(mktemp -d /tmp/pgba_seed_spread_XXXX)}
mkdir -p "$tmp"
[[ -z "${KEEP_DIR:-}" ]] && trap 'rm -rf "$tmp"' EXIT
for ds in "$@"; do
  name=$(basename "$ds")
  base='{}'
  [[ $name == *_ring ]] && base=$(cat "$here/configs/object_ring.json")
  # Features once, shared by every run (`pgba features` takes no config: the rings' preset SIFT
  # options are extracted by each run itself, a few seconds on 640x480 photos).
  mkdir -p "$tmp/feat_$name"
  [[ $name == *_ring ]] || "$bin" -v 0 features --images "$ds/images" --calib "$ds/cameras.txt" --out "$tmp/feat_$name" >/dev/null
  for ((s = 0; s < seeds; ++s)); do
    for v in opengv sampson; do
      out="$tmp/${name}_${v}_$s"
      [[ -f "$out/report.json" ]] && continue
      python3 - "$base" "$v" "$s" >"$out.json" <<'PY'
import json, sys
cfg, variant, seed = json.loads(sys.argv[1]), sys.argv[2], int(sys.argv[3])
rp = {"threshold_px": 1.0, "min_inliers": 40, "seed": seed}
rp.update({"scoring": "opengv", "refine_passes": 2, "refine_until_converged": False} if variant == "opengv"
          else {"scoring": "sampson", "refine_passes": 6, "refine_until_converged": True})
cfg.setdefault("matching", {}).setdefault("verification", {})["relative_pose"] = rp
print(json.dumps(cfg))
PY
      rm -rf "$out"
      cp -r "$tmp/feat_$name" "$out"
      "$bin" -v 0 run --images "$ds/images" --calib "$ds/cameras.txt" --gt "$ds/gt" --out "$out" \
        --config "$out.json" >"$out.log" 2>&1 || echo "warning: $v seed $s on $name failed (log $out.log)" >&2
    done
  done
done
python3 - "$tmp" "$seeds" "$@" <<'PY'
import json, os, statistics, sys
tmp, seeds, dsets = sys.argv[1], int(sys.argv[2]), [os.path.basename(d.rstrip("/")) for d in sys.argv[3:]]
print("dataset | verification | seeds | ms/pair matching (wall, min) | ms/pair verification (thread, min) | "
      "verified matches (min-max) | tracks (min-max) | rot err median deg: per seed | mean | min-max | "
      "rot err max deg: mean | min-max | pairwise rot err median deg: mean | min-max")
print("---|---|---|---|---|---|---|---|---|---|---|---|---|---")
for name in dsets:
    for v in ("opengv", "sampson"):
        med, mx, vm, tr, ms, vs, rel = [], [], [], [], [], [], []
        for s in range(seeds):
            p = f"{tmp}/{name}_{v}_{s}/report.json"
            if not os.path.exists(p):
                continue
            r = json.load(open(p))
            e = r.get("evaluation", {})
            med.append(e.get("rot_err_deg_median", float("nan")))
            mx.append(e.get("rot_err_deg_max", float("nan")))
            rel.append(e.get("rel_rot_err_deg_median", float("nan")))
            vm.append(r["stages"]["match"]["verified_matches"])
            tr.append(r["stages"]["match"].get("tracks", -1))
            ms.append(1000 * r["stages"]["match"]["seconds_per_pair"])
            vs.append(1000 * r["stages"]["match"]["thread_seconds_per_pair_verification"])
        if not med:
            continue
        print(f"{name} | {v} | {len(med)} | {min(ms):.1f} | {min(vs):.1f} | {min(vm)}-{max(vm)} | {min(tr)}-{max(tr)} | "
              f"{' '.join(f'{x:.4f}' for x in med)} | {statistics.mean(med):.4f} | {min(med):.4f}-{max(med):.4f} | "
              f"{statistics.mean(mx):.4f} | {min(mx):.4f}-{max(mx):.4f} | {statistics.mean(rel):.4f} | "
              f"{min(rel):.4f}-{max(rel):.4f}")
PY
