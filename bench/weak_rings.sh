#!/usr/bin/env bash
# Weakly textured objects (docs/benchmarks.md): `pgba run --config CONFIG` on the two Middlebury rings (dino_sparse_ring,
# weakly textured; temple_sparse_ring, the ring that must not get worse), one row per config
# and dataset: features per image, adjacent ring pairs kept by the matching stage, weak pairs
# confirmed / tried (matching.verification.weak_pairs), registered images, rotation error
# median / max against the ground truth (degrees), pgba's wall time.
#
# Usage: bench/weak_rings.sh OUT CONFIG [CONFIG ...]
#   CONFIG: a JSON file (or a preset of configs/). OUT/<config>_<dataset>/ keeps each run's
#   workspace (WS/matching/pairs.txt; bench/pair_errors.py WS GT loop.txt for per-pair errors).
# Environment: PGBA=path/to/pgba (default: build/bin/pgba), DATASETS="dino_sparse_ring
#   temple_sparse_ring".
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
shared=$(cd "$here/.." && pwd)/shared
PGBA=${PGBA:-$here/build/bin/pgba}
[[ $# -ge 2 ]] || { echo "usage: $0 OUT CONFIG [CONFIG ...]" >&2; exit 2; }
out=$1
shift
mkdir -p "$out"
printf "%-22s %-20s %8s %9s %10s %5s %8s %8s %7s\n" config dataset feat/img adj_kept weak_conf reg rot_med rot_max time_s
for cfg in "$@"; do
  for name in ${DATASETS:-dino_sparse_ring temple_sparse_ring}; do
    ds=$shared/datasets/$name
    ws=$out/$(basename "${cfg%.json}")_$name
    rm -rf "$ws"
    t0=$(date +%s.%N)
    "$PGBA" run --config "$cfg" --images "$ds/images" --calib "$ds/cameras.txt" --gt "$ds/gt" --out "$ws" \
      >"$ws.log" 2>&1 || true
    t1=$(date +%s.%N)
    python3 - "$ws" "$ds/loop.txt" "$cfg" "$name" "$(echo "$t1 - $t0" | bc)" <<'EOF'
import json, sys
ws, loop, cfg, name, secs = sys.argv[1:]
ring = [l.strip() for l in open(loop) if l.strip()]
kept, adj, weak, conf = set(), 0, 0, 0
try:
    for l in open(ws + '/matching/pairs.txt'):
        if l.startswith('#') or not l.strip():
            continue
        f = l.split()
        d = abs(ring.index(f[0]) - ring.index(f[1]))
        step = min(d, len(ring) - d)
        if f[6] in ('confirmed', 'leaf', 'unconfirmed'):
            weak += 1
        conf += f[6] in ('confirmed', 'leaf')
        if step == 1 and f[6] in ('verified', 'confirmed', 'leaf'):
            adj += 1
except FileNotFoundError:
    pass
try:
    r = json.load(open(ws + '/report.json'))
except (FileNotFoundError, ValueError):
    r = {}
ev = r.get('evaluation', {})
feats = r.get('stages', {}).get('features', {}).get('features_mean', '')
fmt = lambda v: '%.4f' % v if isinstance(v, (int, float)) else '-'
print('%-22s %-20s %8s %9s %10s %5s %8s %8s %7.1f' % (
    cfg.split('/')[-1].replace('.json', '')[:22], name, ('%.0f' % feats) if feats != '' else '-',
    '%d/%d' % (adj, len(ring)), '%d/%d' % (conf, weak),
    '%s/%d' % (ev.get('images_registered', 0), len(ring)), fmt(ev.get('rot_err_deg_median')),
    fmt(ev.get('rot_err_deg_max')), float(secs)))
EOF
  done
done
