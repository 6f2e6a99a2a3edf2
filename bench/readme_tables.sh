#!/usr/bin/env bash
# Every table of docs/benchmarks.md measured again in one run, with one build. Each section
# calls the script docs/benchmarks.md names for its table, with the arguments given there, and
# keeps its raw output in OUT/<section>.txt; OUT/tables.md gets every table, OUT/log.txt says
# when each section ran and at what load average, and the tables of docs/benchmarks.md (between
# its "<!-- table NAME -->" markers) are replaced by the ones measured (bench/readme_tables.py).
#
#   colmap       bench/compare_colmap.sh: the Strecha sets (default config) and the two rings
#                (configs/object_ring.json), each given the dataset's calibration; the kept
#                pgba workspaces give the real tracks of the pose section
#   colmap_uncal the same, UNCALIBRATED=1 (neither gets a calibration), Strecha sets and temple
#   pose         bench/pose_accuracy.sh on one thread (the time column is the CPU-time ratio):
#                orbit, aerial, planar at seeds 1-4, aerial:1 at 500 images, longfocal seeds
#                1-4, the four real sets' tracks; then configs/paper_triplets.json, and its
#                weighting over 7-view motions (local_motions.kind neighbours, views 7), on
#                some of them. Table 1 comes from the same runs
#   weak         bench/weak_rings.sh with configs/object_ring.json and variants of it
#   selfcal      bench/self_calibration.sh (its default scenes and longfocal:1)
#   realselfcal  bench/real_self_calibration.sh (four datasets, four variants)
#   frontend     bench/front_end_speed.sh, REPEAT=1: the Strecha sets with VARIANTS="before
#                default opencv octave0", the rings with VARIANTS="before default"
#   thousand     bench/thousand_photos.sh, 1000 images
#
# Usage: bench/readme_tables.sh OUT [SECTION...]   (default: every section, in the order above)
#   With SECTIONs, OUT/tables.md is printed again from whatever OUT holds, and only the tables
#   of the sections that OUT holds are replaced in docs/benchmarks.md.
# Environment: PGBA=path/to/pgba (default: build/bin/pgba; copy it elsewhere first if you
#   build while this runs); DOC=FILE writes the tables into FILE instead of docs/benchmarks.md,
#   DOC= (empty) into no file.
# About 25 minutes on an idle 2-core machine. Never run by the tests.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
shared=$(cd "$here/.." && pwd)/shared
datasets=$shared/datasets
[[ $# -ge 1 ]] || { echo "usage: bench/readme_tables.sh OUT [SECTION...]" >&2; exit 2; }
out=$(mkdir -p "$1" && cd "$1" && pwd)
shift
export PGBA=${PGBA:-$here/build/bin/pgba}
[[ -x $PGBA ]] || { echo "error: $PGBA: no pgba binary (build it or set PGBA=)" >&2; exit 2; }
sections=("$@")
[[ ${#sections[@]} -eq 0 ]] && sections=(colmap colmap_uncal pose weak selfcal realselfcal frontend thousand)

log() { echo "$(date -u +%FT%TZ) load $(cut -d' ' -f1-3 /proc/loadavg) $*" | tee -a "$out/log.txt" >&2; }

# The real sets' tracks: from the colmap section's kept workspaces (the same `pgba run` as the
# real rows of docs/benchmarks.md: default config, the dataset's calibration).
real_tracks() {
  local name dir
  for name in fountain_p11 herzjesu_p8 entry_p10 temple_sparse_ring; do
    dir=$(grep -o "/tmp/pgba_vs_colmap_${name}_[A-Za-z0-9]*" "$out/colmap.txt" | tail -1 || true)
    [[ -n $dir && -f $dir/pgba/tracks/points3D.txt ]] || continue
    mkdir -p "$out/tracks"
    ln -sfn "$dir/pgba/tracks" "$out/tracks/$name"
    echo "tracks:$out/tracks/$name:$datasets/$name/gt"
  done
}

# merged_config BASE.json OVERRIDE_JSON: BASE with OVERRIDE merged in, key by key (nested
# objects merged, other values replaced), on stdout.
merged_config() {
  python3 - "$1" "$2" <<'PY'
import json, sys
def merge(a, b):
    for k, v in b.items():
        a[k] = merge(a.get(k, {}), v) if isinstance(v, dict) else v
    return a
print(json.dumps(merge(json.load(open(sys.argv[1])), json.loads(sys.argv[2])), indent=1))
PY
}

run_colmap_uncal() {
  UNCALIBRATED=1 bash "$here/bench/compare_colmap.sh" "$datasets"/{fountain_p11,herzjesu_p8,entry_p10,temple_sparse_ring}
}

run_colmap() {
  KEEP=1 bash "$here/bench/compare_colmap.sh" "$datasets"/{fountain_p11,herzjesu_p8,entry_p10}
  KEEP=1 CONFIG="$here/configs/object_ring.json" bash "$here/bench/compare_colmap.sh" \
    "$datasets"/{temple_sparse_ring,dino_sparse_ring}
}

run_pose() {
  local synthetic=() s
  for s in orbit aerial planar; do synthetic+=("$s:1" "$s:2" "$s:3" "$s:4"); done
  # shellcheck disable=SC2046
  THREADS=1 bash "$here/bench/pose_accuracy.sh" "$out/pose" "${synthetic[@]}" aerial:1:500 \
    longfocal:1 longfocal:2 longfocal:3 longfocal:4 $(real_tracks)
  echo "-- configs/paper_triplets.json"
  # shellcheck disable=SC2046
  THREADS=1 CONFIG="$here/configs/paper_triplets.json" bash "$here/bench/pose_accuracy.sh" "$out/pose_triplets" \
    orbit:1 aerial:1 planar:1 aerial:1:500 longfocal:1 $(real_tracks | grep temple || true)
  echo "-- 7-view motions (configs/paper_triplets.json, local_motions neighbours 7)"
  merged_config "$here/configs/paper_triplets.json" '{"local_motions": {"kind": "neighbours", "views": 7}}' \
    >"$out/seven_view_motions.json"
  THREADS=1 CONFIG="$out/seven_view_motions.json" bash "$here/bench/pose_accuracy.sh" "$out/pose_seven_view" \
    longfocal:1 longfocal:2
}

# The weak-texture variants: the object_ring preset with one change each.
run_weak() {
  local variants=(
    'object_ring:{}'
    'no_leaf_pairs:{"matching": {"verification": {"weak_pairs": {"keep_leaf_pairs": false}}}}'
    'weak_pairs_every_image:{"matching": {"verification": {"weak_pairs": {"max_verified_pairs": 100}}}}'
    'transfer:{"matching": {"verification": {"guided": {"transfer": true}}}}'
    'target4000_ratio09:{"features": {"sift": {"target_features": 4000}}, "matching": {"descriptors": {"max_ratio": 0.9}}}'
  ) configs=() v
  mkdir -p "$out/weak_configs"
  for v in "${variants[@]}"; do
    merged_config "$here/configs/object_ring.json" "${v#*:}" >"$out/weak_configs/${v%%:*}.json"
    configs+=("$out/weak_configs/${v%%:*}.json")
  done
  bash "$here/bench/weak_rings.sh" "$out/weak" "${configs[@]}"
}
run_selfcal() {
  local scenes=() s seed
  for s in orbit aerial planar; do for seed in 1 2 3 4; do scenes+=("$s:$seed"); done; done
  bash "$here/bench/self_calibration.sh" "$out/selfcal" "${scenes[@]}" rendered:1 longfocal:1
}
run_realselfcal() { bash "$here/bench/real_self_calibration.sh" "$out/realselfcal"; }
run_frontend() {
  VARIANTS="before default opencv octave0" REPEAT=1 bash "$here/bench/front_end_speed.sh" \
    "$datasets"/{fountain_p11,herzjesu_p8,entry_p10}
  VARIANTS="before default" REPEAT=1 bash "$here/bench/front_end_speed.sh" "$datasets"/{temple_sparse_ring,dino_sparse_ring}
}
run_thousand() { bash "$here/bench/thousand_photos.sh" "$out/thousand" 1000; }

for s in "${sections[@]}"; do
  declare -F "run_$s" >/dev/null || { echo "error: unknown section '$s' (colmap colmap_uncal pose weak selfcal realselfcal frontend thousand)" >&2; exit 2; }
done
log "start: $PGBA ($(cd "$here" && git rev-parse --short HEAD 2>/dev/null || echo '?')), sections ${sections[*]}"
for s in "${sections[@]}"; do
  log "section $s"
  "run_$s" >"$out/$s.txt" 2>"$out/$s.err" || log "section $s failed (exit $?, see $out/$s.err)"
done
log "done"
doc=${DOC-$here/docs/benchmarks.md}
python3 "$here/bench/readme_tables.py" "$out" ${doc:+"$doc"} >"$out/tables.md"
echo "tables: $out/tables.md${doc:+, written into $doc}" >&2
