"""What a node must publish, computed in Python from the node model and a
Python twin of the test controllers (bit-exact integer arithmetic on the
IEEE bits), and the leaf-by-leaf comparison of received messages."""

from __future__ import annotations

import random

from pyrosgen.frontend.model import NodeModel

from support.ros import bits_of, random_value, rotl64

M64 = 0xFFFFFFFFFFFFFFFF


def landshark_echo(u: dict) -> dict:
    """Twin of tests/ros/controllers/landshark_echo/Controller.c."""
    return {"Out1": (u["In1"] ^ rotl64(u["In2"], 21) ^ rotl64(u["In3"], 42) ^ 0x3FF0000000000000) & M64}


def multi_echo(u: dict) -> dict:
    """Twin of tests/ros/controllers/multi_echo/Fusion.c."""
    return {
        "CmdV": (u["X"] ^ rotl64(u["Y"], 13) ^ rotl64(u["GyroZ"], 29) ^ 0x3FF0000000000000) & M64,
        "CmdW": (u["YawRate"] ^ rotl64(u["AccX"], 7) ^ 0x4000000000000000) & M64,
        "Stopped": (u["EStop"] ^ u["RangeType"] ^ 1) & 1,
        "SeqOut": (u["OdomSeq"] ^ (u["HoldSec"] & 0xFFFFFFFF) ^ (u["RangeType"] << 24) ^ 0xA5A5A5A5) & 0xFFFFFFFF,
        "YawVarOut": u["YawVar"] ^ 0x4008000000000000,
        "WheelCmd": u["FrontRange"],
        "Debug": u["X"],
    }


def as_number(prim: str, value) -> int:
    """A leaf value (driver notation) as an integer: float bits, bool 0/1."""
    if prim in ("float64", "float32"):
        return bits_of(value)
    return int(value)


def zero_inputs(model: NodeModel) -> dict:
    return {f.name: 0 for f in model.controller.inputs.fields}


def inputs_from(model: NodeModel, last: dict[str, dict]) -> dict:
    """Controller_U as the glue fills it from the newest message of each
    topic (``last``: topic -> {leaf path: value}); zero without one."""
    u = zero_inputs(model)
    for r in model.input_relations:
        msg = last.get(r.topic.name)
        if msg is not None:
            u[r.input_field] = as_number(r.path.prim, msg[str(r.path)])
    return u


def random_message(model: NodeModel, msg_type: str, rng: random.Random, mode: str = "random") -> dict:
    """A value for every carried leaf of ``msg_type``."""
    return {str(p): random_value(p.prim, rng, mode, str(p)) for p in model.leaf_paths(msg_type)}


def check_published(model: NodeModel, topic: str, y: dict, leaves: dict) -> list[str]:
    """Differences between a received message on ``topic`` and what the
    output glue must publish for controller outputs ``y``: each related
    field holds its output, bit for bit; every other carried leaf is zero;
    strings and variable-length arrays are empty.  Returns the problems."""
    t = model.topic(topic)
    related = {str(r.path): (r.output_field, r.path.prim) for r in model.output_relations_of(t)}
    carried = {str(p): p.prim for p in model.leaf_paths(t.msg_type)}
    problems = []
    seen = set()
    for path, got in leaves.items():
        if isinstance(got, dict):
            if got.get("str", "") != "" or got.get("var", 0) != 0:
                problems.append(f"{path}: not carried, expected empty, got {got}")
            continue
        seen.add(path)
        if path not in carried:
            problems.append(f"{path}: a scalar leaf that pyrosgen does not carry")
            continue
        prim = carried[path]
        want = y[related[path][0]] if path in related else 0
        have = as_number(prim, got)
        if have != want:
            problems.append(f"{path}: expected {want:#x}, got {have:#x}")
    missing = set(carried) - seen
    if missing:
        problems.append(f"carried leaves not received: {sorted(missing)}")
    return problems
