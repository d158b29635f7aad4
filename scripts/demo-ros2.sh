#!/usr/bin/env bash
# `make demo-ros2`: the main job on ROS 2: build the LandShark node for the
# target ros2 (the same model and proved glue; the C API over rcl), then run
# it against a simulated LandShark (rclpy) whose GPS is spoofed for part of
# the run, on Fast DDS with discovery on the loopback only.  Needs no
# terminal; stops everything it started.
set -euo pipefail
cd "$(dirname "$0")/.."
MODEL=examples/landshark/landshark_controller.yaml
CONTROLLER=examples/landshark/controller
OUT=build/landshark_ros2
echo "demo: pyrosgen build --ros2 $MODEL --controller $CONTROLLER -o $OUT"
.venv/bin/pyrosgen build --ros2 "$MODEL" --controller "$CONTROLLER" -o "$OUT"
echo "demo: running $OUT/bin/landshark_controller on ROS 2 against a simulated LandShark"
exec .venv/bin/python -m pyrosgen.ros2.demo "$OUT" "$@"
