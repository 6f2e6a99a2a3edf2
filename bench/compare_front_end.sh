#!/usr/bin/env bash
# Front-end speed, COLMAP vs pgba, on the same images and the same machine.
#   COLMAP: feature_extractor (CPU SIFT) + exhaustive_matcher (CPU, with its geometric verification)
#   pgba:   pgba features + pgba match (exhaustive pairs, OpenGV verification)
# Both use every core and their defaults (max 8192 features, images downscaled above 3200 px),
# so they do the same amount of work. Prints one table; the workspaces are deleted afterwards.
#
# Usage: bench/compare_front_end.sh [DATASET_DIR ...]
#   DATASET_DIR has images/ and cameras.txt (the layout of shared/datasets/README.md);
#   default: shared/datasets/fountain_p11 and shared/datasets/temple_sparse_ring.
# Environment: PGBA=path/to/pgba (default: the newest build*/bin/pgba of this checkout),
#   COLMAP=path/to/colmap (default: colmap on PATH; Debian: apt-get install colmap),
#   KEEP=1 keeps the workspaces (printed).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
shared=$(cd "$here/.." && pwd)/shared
source "$here/bench/lib.sh"
if [[ $# -eq 0 ]]; then set -- "$shared/datasets/fountain_p11" "$shared/datasets/temple_sparse_ring"; fi

rows=()
for ds in "$@"; do
  name=$(basename "$ds")
  [[ -d "$ds/images" && -f "$ds/cameras.txt" ]] || { echo "error: $ds: needs images/ and cameras.txt" >&2; exit 2; }
  tmp=$(mktemp -d "/tmp/pgba_bench_front_${name}_XXXX")
  t0=$(now)
  colmap_feature_extractor "$ds" "$tmp/colmap.db" "$tmp/colmap_features.log"
  t1=$(now)
  colmap_exhaustive_matcher "$tmp/colmap.db" "$tmp/colmap_match.log"
  t2=$(now)
  "$PGBA" -v 0 features --images "$ds/images" --calib "$ds/cameras.txt" --out "$tmp/ws" >"$tmp/pgba_features.log" 2>&1
  t3=$(now)
  "$PGBA" -v 0 match --out "$tmp/ws" >"$tmp/pgba_match.log" 2>&1
  t4=$(now)

  row=$(python3 - "$tmp" "$name" "$(elapsed "$t0" "$t1")" "$(elapsed "$t1" "$t2")" "$(elapsed "$t2" "$t3")" \
          "$(elapsed "$t3" "$t4")" <<'PY'
import json, sqlite3, sys
tmp, name, cf, cm, pf, pm = sys.argv[1], sys.argv[2], *map(float, sys.argv[3:])
db = sqlite3.connect(f"{tmp}/colmap.db")
n_img = db.execute("select count(*) from images").fetchone()[0]
c_kp = db.execute("select avg(rows) from keypoints").fetchone()[0] or 0
c_pairs = db.execute("select count(*) from two_view_geometries where rows > 0").fetchone()[0]
# Megapixels: from pgba's report (the same images).
rep = json.load(open(f"{tmp}/ws/report.json"))["stages"]
f, m = rep["features"], rep["match"]
mp = f["megapixels_extracted"]
pairs = n_img * (n_img - 1) // 2
print(f"{name} | {n_img} | {mp:.1f} | {cf:.1f} | {pf:.1f} | {cf / mp:.2f} | {pf / mp:.2f} | {cm:.1f} | {pm:.1f} | "
      f"{1000 * cm / pairs:.0f} | {1000 * pm / pairs:.0f} | {c_kp:.0f} / {f['features_mean']:.0f} | "
      f"{c_pairs} / {m['pairs_verified']} of {pairs}")
PY
)
  rows+=("$row")
  if [[ "${KEEP:-0}" == 1 ]]; then echo "kept $tmp" >&2; else rm -rf "$tmp"; fi
done

echo "Front end on $(nproc) cores; wall times in seconds (features include image decoding; COLMAP matching includes its verification)"
echo
echo "dataset | images | MP | features COLMAP | features pgba | s/MP COLMAP | s/MP pgba | matching COLMAP | matching pgba | ms/pair COLMAP | ms/pair pgba | features/image COLMAP / pgba | verified pairs COLMAP / pgba"
echo "---|---|---|---|---|---|---|---|---|---|---|---|---"
printf '%s\n' "${rows[@]}"
