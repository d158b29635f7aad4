#!/usr/bin/env bash
# `make demo-ros2`: the main job on ROS 2: build the LandShark node for the
# target ros2 (the same model and proved glue; the C API over rcl), then run
# it against a simulated LandShark (rclpy) whose GPS is spoofed for part of
# the run, on Fast DDS with discovery on the loopback only.  Needs no
# terminal; stops everything it started.  Then the three-node system of
# examples/system_chain, built with `system build --ros2` and run the same way.
set -euo pipefail
cd "$(dirname "$0")/.."
MODEL=examples/landshark/landshark_controller.yaml
CONTROLLER=examples/landshark/controller
OUT=build/landshark_ros2
echo "demo: pyrosgen build --ros2 $MODEL --controller $CONTROLLER -o $OUT"
.venv/bin/pyrosgen build --ros2 "$MODEL" --controller "$CONTROLLER" -o "$OUT"
echo "demo: running $OUT/bin/landshark_controller on ROS 2 against a simulated LandShark"
.venv/bin/python -m pyrosgen.ros2.demo "$OUT" "$@"

SYSTEM=examples/system_chain/system.yaml
SYSTEM_OUT=build/system_chain_ros2
echo
echo "demo: pyrosgen system build --ros2 $SYSTEM -o $SYSTEM_OUT   (a system: laser guard -> velocity mux -> base)"
.venv/bin/pyrosgen system build --ros2 "$SYSTEM" -o "$SYSTEM_OUT"
echo "demo: the chain's links and chains: $SYSTEM_OUT/guard_chain.certificate.md"
sed -n '/^## Chains/,/^## Transport/p' "$SYSTEM_OUT/guard_chain.certificate.md" | sed '$d'
echo "demo: running the chain on ROS 2 (each node as $SYSTEM_OUT/guard_chain.launch.xml starts it)"
exec .venv/bin/python -m pyrosgen.system.demo_dds "$SYSTEM_OUT"
