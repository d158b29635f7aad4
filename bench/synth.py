"""Synthetic node models for the benchmarks (BENCHMARKS.md).

``synth.py N OUTDIR`` writes ``OUTDIR/synth_N.yaml`` (a valid node model
with N relations) and ``OUTDIR/controller/`` (a Simulink-style controller
``Controller.c``/``Controller.h``/``rtwtypes.h`` for it).

Shape (chosen to look like a real sensor-fusion node, and to grow the
generated program linearly with N):

- ``n_out = max(1, N // 4)`` controller outputs and ``n_in = N - n_out``
  inputs (N = 4 gives LandShark's 3 inputs and 1 output);
- the inputs are fed by ``n_in`` relations over distinct leaves of
  ``ceil(n_in / PER_TOPIC)`` subscribed ``nav_msgs/Odometry`` topics
  (88 carried leaves each: ``header.seq``, ``header.stamp.sec/nsec``
  (``uint32``), the pose and twist with their two ``covariance[36]``
  arrays (``float64``)); each topic feeds at most ``PER_TOPIC`` inputs,
  its leaves taken in order, so most inputs are ``float64`` and a few
  (the header leaves) ``uint32``;
- each output feeds one ``float64`` leaf of one of
  ``ceil(n_out / PER_TOPIC)`` published ``nav_msgs/Odometry`` topics.

Every subscribed topic's callback copies all 88 leaves (DESIGN.md
section 5), so the generated glue has about ``88 * n_in / PER_TOPIC +
n_in + n_out`` assignments: linear in N.

The controller computes each output as a sum over a slice of the inputs
(plain C, no dependency), so that the node can be compiled and run.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

#: Relations per topic (of the 88 leaves of nav_msgs/Odometry).
PER_TOPIC = 64
MSG = "nav_msgs/Odometry"


def odometry_leaves() -> list[tuple[str, str]]:
    """The carried leaves of nav_msgs/Odometry as ``(path, prim)``, in
    declaration order (computed by pyrosgen's own message registry)."""
    from pyrosgen.frontend.msgmodel import leaf_paths
    from pyrosgen.frontend.msgload import MsgRegistry

    reg = MsgRegistry()
    reg.carried(MSG)
    prim = {"double": "float64", "unsigned int": "uint32"}
    return [(str(p), prim[p.c_type]) for p in leaf_paths(MSG, reg.messages())]


def shape(n: int) -> tuple[int, int]:
    """``(n_in, n_out)`` for N relations."""
    if n < 2:
        raise ValueError("N must be at least 2")
    n_out = max(1, n // 4)
    return n - n_out, n_out


def model_yaml(n: int, period_ms: int = 20, name: str | None = None) -> tuple[str, list[tuple[str, str]], list[str]]:
    """The model text, the inputs ``(name, prim)`` and the output names."""
    leaves = odometry_leaves()
    n_in, n_out = shape(n)
    name = name or f"synth_{n}"
    sub_topics = [f"/synth/odom_{i:03d}" for i in range(math.ceil(n_in / PER_TOPIC))]
    dbl_leaves = [p for p, t in leaves if t == "float64"]
    pub_topics = [f"/synth/cmd_{i:03d}" for i in range(math.ceil(n_out / PER_TOPIC))]
    inputs: list[tuple[str, str]] = []
    in_rels: list[str] = []
    for k in range(n_in):
        topic = sub_topics[k // PER_TOPIC]
        path, prim = leaves[k % PER_TOPIC]
        field = f"In{k + 1}"
        inputs.append((field, prim))
        in_rels.append(f"    - {{topic: {topic}, field: '{path}', input: {field}}}")
    outputs = [f"Out{k + 1}" for k in range(n_out)]
    out_rels = [
        f"    - {{output: {o}, topic: {pub_topics[k // PER_TOPIC]}, field: '{dbl_leaves[k % PER_TOPIC]}'}}"
        for k, o in enumerate(outputs)
    ]
    lines = [
        f"# Synthetic benchmark node with {n} relations ({n_in} inputs, {n_out} outputs),",
        "# written by bench/synth.py.",
        "node:",
        f"  name: {name}",
        f"  period_ms: {period_ms}",
        "controller:",
        "  name: Controller",
        "  inputs:",
        "    name: Controller_U",
        "    fields:",
        *[f"      {f}: {t}" for f, t in inputs],
        "  outputs:",
        "    name: Controller_Y",
        "    fields:",
        *[f"      {o}: float64" for o in outputs],
        "topics:",
        *[f"  - {{name: {t}, direction: subscribe, type: {MSG}, queue_size: 1}}" for t in sub_topics],
        *[f"  - {{name: {t}, direction: publish, type: {MSG}, queue_size: 1}}" for t in pub_topics],
        "relations:",
        "  inputs:",
        *in_rels,
        "  outputs:",
        *out_rels,
        "msg_paths: []",
        "",
    ]
    return "\n".join(lines), inputs, outputs


_CTYPE = {"float64": "real_T", "uint32": "uint32_T"}

RTWTYPES = """\
/* rtwtypes.h: Simulink base types (written by bench/synth.py). */
#ifndef RTWTYPES_H
#define RTWTYPES_H
typedef unsigned int uint32_T;
typedef double real_T;
#endif
"""


def controller_files(inputs: list[tuple[str, str]], outputs: list[str]) -> dict[str, str]:
    """``Controller.h``, ``Controller.c`` and ``rtwtypes.h`` of a controller
    whose output k is the sum of the inputs i with ``i % n_out == k``."""
    h = [
        "/* Controller.h: synthetic Simulink-style controller (bench/synth.py). */",
        "#ifndef RTW_HEADER_Controller_h_",
        "#define RTW_HEADER_Controller_h_",
        '#include "rtwtypes.h"',
        "typedef struct {",
        *[f"  {_CTYPE[t]} {f};" for f, t in inputs],
        "} ExtU_Controller_T;",
        "typedef struct {",
        *[f"  real_T {o};" for o in outputs],
        "} ExtY_Controller_T;",
        "extern ExtU_Controller_T Controller_U;",
        "extern ExtY_Controller_T Controller_Y;",
        "extern void Controller_initialize(void);",
        "extern void Controller_step(void);",
        "extern void Controller_terminate(void);",
        "#endif",
        "",
    ]
    n_out = len(outputs)
    sums: list[list[str]] = [[] for _ in outputs]
    for i, (f, _t) in enumerate(inputs):
        sums[i % n_out].append(f"(real_T)Controller_U.{f}")
    c = [
        "/* Controller.c: synthetic Simulink-style controller (bench/synth.py). */",
        '#include "Controller.h"',
        "ExtU_Controller_T Controller_U;",
        "ExtY_Controller_T Controller_Y;",
        "void Controller_step(void)",
        "{",
        *[f"  Controller_Y.{o} = {' + '.join(s) if s else '0.0'};" for o, s in zip(outputs, sums)],
        "}",
        "void Controller_initialize(void)",
        "{",
        *[f"  Controller_U.{f} = 0;" for f, _t in inputs],
        *[f"  Controller_Y.{o} = 0.0;" for o in outputs],
        "}",
        "void Controller_terminate(void)",
        "{",
        "}",
        "",
    ]
    return {"Controller.h": "\n".join(h), "Controller.c": "\n".join(c), "rtwtypes.h": RTWTYPES}


def write(n: int, out_dir: Path, period_ms: int = 20) -> Path:
    """Write the model and its controller into ``out_dir``; return the
    model's path."""
    out_dir.mkdir(parents=True, exist_ok=True)
    text, inputs, outputs = model_yaml(n, period_ms)
    path = out_dir / f"synth_{n}.yaml"
    path.write_text(text, encoding="ascii")
    cdir = out_dir / "controller"
    cdir.mkdir(exist_ok=True)
    for name, body in controller_files(inputs, outputs).items():
        (cdir / name).write_text(body, encoding="ascii")
    return path


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("n", type=int, help="number of relations (>= 2)")
    ap.add_argument("out_dir", type=Path)
    ap.add_argument("--period-ms", type=int, default=20)
    a = ap.parse_args(argv)
    print(write(a.n, a.out_dir, a.period_ms))
    return 0


if __name__ == "__main__":
    sys.exit(main())
