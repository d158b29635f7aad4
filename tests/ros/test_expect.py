"""The checkers of the real-ROS tests have teeth (no ROS needed)."""

from __future__ import annotations

import random

from pyrosgen.frontend.validate import load_model

from support import expect
from support import ros as rosutil


def _published(model, topic, y):
    """A message exactly as the output glue must build it."""
    t = model.topic(topic)
    related = {str(r.path): r.output_field for r in model.output_relations_of(t)}
    out = {}
    for p in model.leaf_paths(t.msg_type):
        v = y[related[str(p)]] if str(p) in related else 0
        out[str(p)] = rosutil.d(v) if p.prim == "float64" else rosutil.f(v) if p.prim == "float32" else v
    return out


def test_check_published_accepts_the_right_message_and_catches_one_bit():
    model = load_model(rosutil.MULTI)
    rng = random.Random(0)
    msgs = {t.name: expect.random_message(model, t.msg_type, rng) for t in model.subscribed}
    y = expect.multi_echo(expect.inputs_from(model, msgs))
    for t in model.published:
        good = _published(model, t.name, y)
        good["note" if t.name == "/fusion/status" else "_none"] = {"str": ""}
        good.pop("_none", None)
        assert expect.check_published(model, t.name, y, good) == []
        for path in [p for p in good if not isinstance(good[p], dict)]:
            bad = dict(good)
            v = bad[path]
            bad[path] = (v[:-1] + format(int(v[-1], 16) ^ 1, "x")) if isinstance(v, str) else v ^ 1
            assert expect.check_published(model, t.name, y, bad), path
        bad = dict(good)
        bad.pop(next(iter(bad)))
        assert expect.check_published(model, t.name, y, bad)
    status = _published(model, "/fusion/status", y)
    status["note"] = {"str": "x"}
    assert expect.check_published(model, "/fusion/status", y, status)


def test_twins_depend_on_every_input():
    model = load_model(rosutil.MULTI)
    zero = expect.zero_inputs(model)
    base = expect.multi_echo(zero)
    for f in model.controller.inputs.fields:
        u = dict(zero, **{f.name: 1})
        assert expect.multi_echo(u) != base, f.name
    lz = {"In1": 0, "In2": 0, "In3": 0}
    assert expect.landshark_echo(lz) == {"Out1": rosutil.dbits(1.0)}
    for k in lz:
        assert expect.landshark_echo(dict(lz, **{k: 1 << 63})) != {"Out1": rosutil.dbits(1.0)}
