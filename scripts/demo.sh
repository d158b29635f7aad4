#!/usr/bin/env bash
# The main job on the LandShark example (`make demo`, after deps and proofs):
# build the node (glue generated and proved by Coq, C API over roscpp, layout
# check, compile and link), then run it on a private rosmaster against a
# simulated robot whose GPS is spoofed for part of the run.  Then the
# timeouts (rule 4.12): build the velocity guard (examples/velocity_guard)
# and run it on a private rosmaster while its two command sources fall
# silent one after the other: the command before and after each stops.
# Then a system (DESIGN.md section 10): build the three-node chain of
# examples/system_chain (in parallel, cached), show its certificate's chains,
# and run it: the wheel speeds for a clear scan, an obstacle, a teleop command.
# Needs no terminal; stops everything it started; builds rewrite only what
# changed.
# With DIAGRAM=1 (`make demo DIAGRAM=1`), the controller is the block
# diagram of examples/landshark/landshark_diagram.yaml: Coq generates and
# proves it too, and the node is built without a controller folder.
set -euo pipefail
# `python -m pyrosgen` from the repository root: this checkout's pyrosgen, whatever
# the venv's console script was installed from
cd "$(dirname "$0")/.."
if [ "${DIAGRAM:-0}" = 1 ]; then
  MODEL=examples/landshark/landshark_diagram.yaml
  OUT=build/landshark_diagram
  echo "demo: pyrosgen build $MODEL -o $OUT   (the controller: a block diagram, generated and proved)"
  .venv/bin/python -m pyrosgen build "$MODEL" -o "$OUT"
else
  MODEL=examples/landshark/landshark_controller.yaml
  CONTROLLER=examples/landshark/controller
  OUT=build/landshark
  echo "demo: pyrosgen build $MODEL --controller $CONTROLLER -o $OUT"
  .venv/bin/python -m pyrosgen build "$MODEL" --controller "$CONTROLLER" -o "$OUT"
fi
echo "demo: running $OUT/bin/landshark_controller against a simulated LandShark"
.venv/bin/python -m pyrosgen.ros.demo "$OUT"

GUARD=examples/velocity_guard/velocity_guard.yaml
GUARD_OUT=build/velocity_guard
echo
echo "demo: pyrosgen build $GUARD -o $GUARD_OUT   (timeouts: a silent source is replaced, rule 4.12)"
.venv/bin/python -m pyrosgen build "$GUARD" -o "$GUARD_OUT"
echo "demo: running $GUARD_OUT/bin/velocity_guard: teleop falls silent at 2 s, nav at 4 s"
.venv/bin/python -m pyrosgen.ros.demo_guard "$GUARD_OUT"

SYSTEM=examples/system_chain/system.yaml
SYSTEM_OUT=build/system_chain
echo
echo "demo: pyrosgen system build $SYSTEM -o $SYSTEM_OUT   (a system: laser guard -> velocity mux -> base)"
.venv/bin/pyrosgen system build "$SYSTEM" -o "$SYSTEM_OUT"
echo "demo: the chain's links and chains: $SYSTEM_OUT/guard_chain.certificate.md"
sed -n '/^## Chains/,/^## Transport/p' "$SYSTEM_OUT/guard_chain.certificate.md" | sed '$d'
echo "demo: running the chain: a clear scan, an obstacle, then a teleop command"
exec .venv/bin/python -m pyrosgen.system.demo "$SYSTEM_OUT"
