#!/usr/bin/env bash
# The main job on the built-in default: installs, builds, and runs pgba on a synthetic scene
# through every stage that exists, ending with the evaluation table.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
OUT=${OUT:-demo_out}
build/bin/pgba synth --scenario longfocal --out "$OUT/scene" --seed 1 --noise 0.5 --outliers 0.02 >/dev/null
# Until the adjustment stages land, the ground truth itself is evaluated (sigma at the noise level).
build/bin/pgba evaluate "$OUT/scene/gt" --obs "$OUT/scene/input" --gt "$OUT/scene/gt" --loop "$OUT/scene/loop_pairs.txt" --json "$OUT/evaluation.json"
echo "demo: outputs in $OUT/ (evaluation.json)"
