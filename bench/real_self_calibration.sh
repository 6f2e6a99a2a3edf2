#!/usr/bin/env bash
# Self-calibration on real images (docs/benchmarks.md): each dataset of /work/shared/datasets (images/, cameras.txt,
# gt/) run with `pgba run` in four variants, for one or two builds back to back (so their
# ratios hold on a shared machine):
#   cal     the dataset's calibration, held (--calib D/cameras.txt): the reference;
#   nocal   no calibration (links to the photos in a folder without cameras.txt: SIMPLE_RADIAL
#           prior at 1.2 max(w, h), view-graph focal, focal, k and, for a camera with neither a
#           calibration nor EXIF, the principal point refined);
#   nocal_pp  the same with {"intrinsics": {"refine_principal_point": true}};
#   f110    a PINHOLE copy of the calibration with fx, fy x 1.1 and --calib-prior.
# The features of the first run are copied to the others (same photos and options).
# One row per (build, dataset, variant): registered, focal error against the dataset's
# (fx + fy) / 2 (%), principal point, rotation error median after Sim(3) alignment
# (rot_err_deg_median) and gauge-free over all pairs (rel_rot_err_deg_median), both also as
# ratios to the same build's `cal` run.
#
# Usage: bench/real_self_calibration.sh OUT [DATASET...]
#   (default: temple_sparse_ring fountain_p11 herzjesu_p8 entry_p10)
# Environment: PGBA (default: newest build*/bin/pgba), PGBA_BASE (a second build, e.g.
# another branch's, run first under the name "base"), TAG (PGBA's name, default "new"), DATASETS (default /work/shared/datasets),
# VARIANTS (default "cal nocal nocal_pp f110").
set -euo pipefail
if [[ $# -lt 1 ]]; then
  echo "usage: $0 OUT [DATASET...]" >&2
  exit 2
fi
out=$1
shift
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/pgba_binary.sh"
root=${DATASETS:-/work/shared/datasets}
variants=(${VARIANTS:-cal nocal nocal_pp f110})
sets=("$@")
[[ ${#sets[@]} -eq 0 ]] && sets=(temple_sparse_ring fountain_p11 herzjesu_p8 entry_p10)
builds=("${TAG:-new}:$PGBA")
[[ -n "${PGBA_BASE:-}" ]] && builds=("base:$PGBA_BASE" "${builds[@]}")
mkdir -p "$out"
echo '{"intrinsics": {"refine_principal_point": true}}' >"$out/refine_pp.json"

for name in "${sets[@]}"; do
  ds=$root/$name
  [[ -f $ds/cameras.txt && -d $ds/gt ]] || { echo "error: $ds: no cameras.txt or gt/" >&2; exit 2; }
  data=$out/data/$name
  mkdir -p "$data/images_nocal"
  for f in "$ds"/images/*; do ln -sfn "$f" "$data/images_nocal/"; done
  awk '/^#/ {print; next} NF {printf "%s PINHOLE %s %s %.6f %.6f %s %s\n", $1, $3, $4, 1.1 * $5, 1.1 * $6, $7, $8}' \
    "$ds/cameras.txt" >"$data/cameras_f110.txt"
  for build in "${builds[@]}"; do
    tag=${build%%:*}
    bin=${build#*:}
    for v in "${variants[@]}"; do
      run=$out/$tag/$name/$v
      rm -rf "$run"
      mkdir -p "$run"
      [[ -d $out/features_$name ]] && cp -r "$out/features_$name" "$run/features"
      case $v in
        cal) args=(--images "$ds/images" --calib "$ds/cameras.txt") ;;
        nocal) args=(--images "$data/images_nocal") ;;
        nocal_pp) args=(--images "$data/images_nocal" --config "$out/refine_pp.json") ;;
        f110) args=(--images "$ds/images" --calib "$data/cameras_f110.txt" --calib-prior) ;;
        *) echo "error: unknown variant $v" >&2; exit 2 ;;
      esac
      "$bin" run "${args[@]}" --gt "$ds/gt" --out "$run" >"$run.log" 2>&1 || echo "($tag $name $v failed: $run.log)"
      [[ -d $out/features_$name ]] || cp -r "$run/features" "$out/features_$name"
    done
  done
done

python3 - "$out" "$root" "${sets[@]}" <<'EOF'
import json, os, sys
out, root, sets = sys.argv[1], sys.argv[2], sys.argv[3:]
def cam(path):
    for line in open(path):
        if line.strip() and not line.startswith('#'):
            p = line.split()
            return p[1], [float(x) for x in p[4:]]
def focal_pp(model, p):
    one = model in ('SIMPLE_PINHOLE', 'SIMPLE_RADIAL', 'RADIAL')
    return (p[0], p[1], p[2]) if one else ((p[0] + p[1]) / 2, p[2], p[3])
print("| build | dataset | variant | registered | focal err % | pp (cx, cy) | rot err median (Sim3) | ratio | rel. rot err median | ratio |")
print("|---|---|---|---|---|---|---|---|---|---|")
for tag in sorted(d for d in os.listdir(out) if os.path.isdir(os.path.join(out, d)) and d not in ('data',) and not d.startswith('features_')):
    for name in sets:
        _, truth = cam(os.path.join(root, name, 'cameras.txt'))
        f_true = (truth[0] + truth[1]) / 2
        ref = None
        for v in ('cal', 'nocal', 'nocal_pp', 'f110'):
            run = os.path.join(out, tag, name, v)
            try:
                r = json.load(open(os.path.join(run, 'report.json')))
                e = r['evaluation']
                model, p = cam(os.path.join(run, 'sparse', 'cameras.txt'))
            except (OSError, KeyError, ValueError):
                if os.path.isdir(run): print(f"| {tag} | {name} | {v} | failed | | | | | | |")
                continue
            f, cx, cy = focal_pp(model, p)
            sim3, rel = e['rot_err_deg_median'], e['rel_rot_err_deg_median']
            if v == 'cal': ref = (sim3, rel)
            ratio = lambda a, b: f"{a / b:.2f}x" if b else ""
            print(f"| {tag} | {name} | {v} | {r['images_registered']}/{r['images_input']} | {100 * (f / f_true - 1):+.3f} "
                  f"| {cx:.1f}, {cy:.1f} | {sim3:.4f} | {ratio(sim3, ref[0]) if ref else ''} | {rel:.4f} "
                  f"| {ratio(rel, ref[1]) if ref else ''} |")
EOF
