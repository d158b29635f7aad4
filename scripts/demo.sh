#!/usr/bin/env bash
# The main job on the LandShark example (`make demo`, after deps and proofs):
# build the node (glue generated and proved by Coq, C API over roscpp, layout
# check, compile and link), then run it on a private rosmaster against a
# simulated robot whose GPS is spoofed for part of the run.  Needs no
# terminal; stops everything it started.
set -euo pipefail
cd "$(dirname "$0")/.."
MODEL=examples/landshark/landshark_controller.yaml
CONTROLLER=examples/landshark/controller
OUT=build/landshark
echo "demo: pyrosgen build $MODEL --controller $CONTROLLER -o $OUT"
.venv/bin/pyrosgen build "$MODEL" --controller "$CONTROLLER" -o "$OUT"
echo "demo: running $OUT/bin/landshark_controller against a simulated LandShark"
exec .venv/bin/python -m pyrosgen.ros.demo "$OUT"
