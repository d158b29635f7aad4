#!/usr/bin/env bash
# The main job on the LandShark example. Grows with the project: today it
# validates the model; see README for what each stage does.
set -euo pipefail
cd "$(dirname "$0")/.."
MODEL=examples/landshark/landshark_controller.yaml
echo "demo: pyrosgen check $MODEL"
.venv/bin/pyrosgen check "$MODEL"
echo "demo: the LandShark node model is valid"
