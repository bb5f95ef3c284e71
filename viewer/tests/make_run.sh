#!/usr/bin/env bash
# The viewer tests' map: the demo street (30 frames) simulated and mapped with the simulated
# segmenter looking for cars and people, textured. Usage: make_run.sh ARTEMIS OUT_DIR
set -euo pipefail
artemis=$1
out=$2
rm -rf "$out"
mkdir -p "$out"
"$artemis" --log-level warn sim --preset demo --frames 30 --out "$out/sim" > "$out/sim.log"
"$artemis" --log-level warn run "$out/sim" --query "cars and people" --segmenter sim --out "$out/run" > "$out/run.log"
