"""The C++ roscpp wrapper is part of the trust base (DESIGN.md section 7):
round trips of every carried field of every message type used in the tests
through a real master.

A test model subscribes ``/rt/in_<x>`` and publishes ``/rt/out_<x>`` for
each type; a C echo harness linked with the generated wrapper copies each
received struct into a global ring and publishes it from its loop.  rospy
sends messages whose every carried leaf is set (extremes, NaN payloads,
signalling NaNs, signed zeros, subnormals, random bits) and whose strings and
variable-length arrays are not empty; the echo must carry every leaf bit for
bit and come back with empty strings and arrays."""

from __future__ import annotations

import random

from support import expect
from support import ros as rosutil
from support.ros import ROUNDTRIP_TYPES, received, run_driver, same_leaf, start_node

#: Messages per type: one each of the fixed modes, then random ones.
MODES = ["zero", "min", "max", "special", "special", "special"] + ["random"] * 14


def test_wrapper_round_trip_every_carried_leaf(ros, roundtrip, tmp_path):
    binary, model = roundtrip
    rng = random.Random(1234)
    sent: dict[str, list[dict]] = {}
    steps = []
    for short, t in ROUNDTRIP_TYPES.items():
        topic = f"/rt/in_{short}"
        sent[topic] = [expect.random_message(model, t, rng, m) for m in MODES]
    # interleave the types; a short pause now and then lets the echoes flow
    for i in range(len(MODES)):
        for topic, msgs in sent.items():
            steps.append({"publish": {"topic": topic, "values": msgs[i], "fill_noncarried": True}})
        steps.append({"sleep": 0.02})
    for short in ROUNDTRIP_TYPES:
        steps.append({"wait_count": {"topic": f"/rt/out_{short}", "count": len(MODES), "timeout": 20}})
    plan = {
        "msg_paths": rosutil.CUSTOM_MSG_PATHS,
        "publishers": [{"topic": f"/rt/in_{s}", "type": t, "queue_size": 1000} for s, t in ROUNDTRIP_TYPES.items()],
        "subscribers": [{"topic": f"/rt/out_{s}", "type": t} for s, t in ROUNDTRIP_TYPES.items()],
        "steps": steps,
        "linger": 0.3,
    }
    start_node(ros, binary, tmp_path / "harness.log")
    result = run_driver(ros, plan, tmp_path)
    problems = []
    checked = 0
    for short, t in ROUNDTRIP_TYPES.items():
        echoes = received(result, f"/rt/out_{short}")
        assert len(echoes) == len(MODES), f"{t}: {len(echoes)} echoes for {len(MODES)} messages"
        carried = {str(p): p.prim for p in model.leaf_paths(t)}
        for i, (want, got) in enumerate(zip(sent[f"/rt/in_{short}"], echoes)):
            leaves = got["leaves"]
            scalars = {p for p, v in leaves.items() if not isinstance(v, dict)}
            # pyrosgen's carried view = every scalar leaf of the full definition
            if scalars != set(carried):
                problems.append(f"{t}: carried {sorted(set(carried) ^ scalars)} differ from the definition")
            for path, prim in carried.items():
                checked += 1
                if not same_leaf(prim, want[path], leaves.get(path)):
                    problems.append(f"{t} #{i} {path} ({prim}): sent {want[path]}, echoed {leaves.get(path)}")
            for path, v in leaves.items():
                if isinstance(v, dict) and (v.get("str", "") != "" or v.get("var", 0) != 0):
                    problems.append(f"{t} #{i} {path}: not carried, must come back empty, got {v}")
    assert not problems, "\n".join(problems[:50])
    assert checked > 1000


def test_round_trip_sends_what_it_claims(roundtrip):
    """The values sent above do exercise the special cases: NaN payloads,
    float64 signalling NaNs, -0.0, integer extremes."""
    _, model = roundtrip
    rng = random.Random(1234)
    f64, ints = set(), set()
    for t in ROUNDTRIP_TYPES.values():
        for m in MODES:
            msg = expect.random_message(model, t, rng, m)
            for p in model.leaf_paths(t):
                v = msg[str(p)]
                if p.prim == "float64":
                    f64.add(rosutil.bits_of(v))
                elif p.prim in rosutil.INT_RANGES and not str(p).endswith("nsec"):
                    ints.add((p.prim, v))
    assert 0x8000000000000000 in f64 and 0x7FF0000000000001 in f64 and 0x7FF8DEADBEEF1234 in f64
    assert ("uint32", 2**32 - 1) in ints and ("int32", -2**31) in ints and ("uint8", 255) in ints
