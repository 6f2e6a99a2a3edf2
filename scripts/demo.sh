#!/usr/bin/env bash
# The main job on the built-in default: installs, builds, renders a synthetic image scene
# (a textured room seen from a ring of 20 known poses) and runs the whole pipeline on it:
# SIFT, matching, triplets, averaging, local hessians, pointless global BA, evaluation
# against the scene's ground truth. Open demo_out/run/report.html afterwards.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
OUT=${OUT:-demo_out}
build/bin/pgba synth --render --out "$OUT/scene" --seed 1
build/bin/pgba run --images "$OUT/scene/images" --calib "$OUT/scene/cameras.txt" --gt "$OUT/scene/gt" \
  --out "$OUT/run"
echo "demo: open $OUT/run/report.html (model: $OUT/run/sparse/, points: $OUT/run/points.ply)"
