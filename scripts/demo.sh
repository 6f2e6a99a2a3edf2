#!/usr/bin/env bash
# The main job on the built-in default: installs, builds, and runs pgba on a synthetic scene
# through every stage that exists, ending with the evaluation table.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
OUT=${OUT:-demo_out}
S="$OUT/scene"
build/bin/pgba synth --scenario orbit --out "$S" --seed 1 --noise 0.5 --outliers 0.02
# Global initialisation from the scene's tracks (poses unknown): pairs, triplets, averaging.
build/bin/pgba init --tracks "$S/input" --out "$OUT/ws"
# Evaluation of the initial poses against the truth.
build/bin/pgba evaluate "$OUT/ws/init" --obs "$S/input" --gt "$S/gt" --json "$OUT/evaluation.json"
echo "demo: workspace in $OUT/ws (report.json, init/), evaluation in $OUT/evaluation.json"
