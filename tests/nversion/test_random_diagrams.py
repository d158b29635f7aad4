"""Random block diagrams (hypothesis): every one the front end accepts
has the same diagram text in both readings (``pyrosgen.nversion``):
every block kind, float64, float32, int32 and bool signals, decimal
constants rounded once, delays fed back from later blocks, integrators
(``gain * T``), subsystems instantiated, and the blocks listed out of
evaluation order.  The generator writes valid diagrams, and the test
requires the front end to accept them."""

from __future__ import annotations

import tempfile
from pathlib import Path

import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pyrosgen.frontend.validate import load_model
from pyrosgen.nversion import diagram
from pyrosgen.proof.modeltext import diagram_text

SETTINGS = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])


class Num(str):
    """A decimal written as a plain YAML number."""


yaml.SafeDumper.add_representer(Num, lambda d, v: d.represent_scalar("tag:yaml.org,2002:float", str(v)))

DEC = st.builds(lambda s, a, b, e: Num(f"{s}{a}.{b}e{e:+d}" if e else f"{s}{a}.{b}"),
                st.sampled_from(["", "-"]), st.integers(0, 999), st.integers(0, 99999), st.integers(-8, 8))
INPUTS = {"In1": "float64", "In2": "float64", "F1": "float32", "I1": "int32", "B1": "bool"}
TOPIC_TYPE = {"float64": "std_msgs/Float64", "float32": "std_msgs/Float32", "int32": "std_msgs/Int32",
              "bool": "std_msgs/Bool"}


@st.composite
def diagrams(draw):
    sig: dict[str, str] = dict(INPUTS)
    blocks, delays = [], []

    def pick(t):
        return draw(st.sampled_from(sorted(n for n, q in sig.items() if q == t)))

    for i in range(draw(st.integers(1, 14))):
        name = f"b{i}"
        t = draw(st.sampled_from(["float64", "float64", "float32", "int32", "bool"]))
        num = {"int32": st.integers(-1000, 1000)}.get(t, DEC)
        kinds = {"bool": ["RelationalOperator", "Logic", "Constant"],
                 "int32": ["Constant", "Gain", "Sum", "MinMax", "Saturation", "Switch", "UnitDelay"]}.get(
            t, ["Constant", "Gain", "Sum", "Product", "Divide", "Abs", "MinMax", "Saturation", "Switch",
                "UnitDelay", "DiscreteIntegrator"])
        kind = draw(st.sampled_from(kinds))
        b = {"name": name, "block": kind}
        if kind == "Constant":
            b.update(type=t, value=draw(st.booleans()) if t == "bool" else draw(num))
        elif kind == "Gain":
            b.update(input=pick(t), gain=draw(num))
        elif kind == "Sum":
            ins = draw(st.lists(st.just(0), min_size=1, max_size=3))
            b.update(inputs=[pick(t) for _ in ins])
            if draw(st.booleans()):
                b["signs"] = "".join(draw(st.sampled_from("+-")) for _ in ins)
        elif kind in ("Product", "Divide"):
            b.update(inputs=[pick(t), pick(t)])
        elif kind == "Abs":
            b.update(input=pick(t))
        elif kind == "MinMax":
            b.update(function=draw(st.sampled_from(["min", "max"])), inputs=[pick(t), pick(t)])
        elif kind == "Saturation":
            lo, hi = sorted([draw(st.integers(-1000, 1000)), draw(st.integers(-1000, 1000))])
            b.update(input=pick(t), lower=lo if t == "int32" else Num(f"{lo}.5"),
                     upper=hi if t == "int32" else Num(f"{hi}.5"))
        elif kind == "RelationalOperator":
            q = draw(st.sampled_from(["float64", "float32", "int32"]))
            b.update(operator=draw(st.sampled_from(["==", "~=", "!=", "<", "<=", ">", ">="])),
                     inputs=[pick(q), pick(q)])
        elif kind == "Logic":
            op = draw(st.sampled_from(["AND", "OR", "NAND", "NOR", "XOR", "NOT"]))
            b.update(operator=op, inputs=[pick("bool")] if op == "NOT" else [pick("bool"), pick("bool")])
        elif kind == "Switch":
            crit = draw(st.sampled_from(["u2 >= threshold", "u2 > threshold", "u2 ~= 0"]))
            q = draw(st.sampled_from(["float64", "int32"] + (["bool"] if crit == "u2 ~= 0" else [])))
            b.update(inputs=[pick(t), pick(q), pick(t)], criterion=crit)
            if crit != "u2 ~= 0":
                b["threshold"] = draw(st.integers(-5, 5)) if q == "int32" else draw(DEC)
        elif kind == "UnitDelay":
            b["type"] = t
            if draw(st.booleans()):
                b["initial"] = draw(num)
            delays.append(b)          # its input: any signal of its type, later ones too
        else:
            if draw(st.booleans()):
                b["gain"] = draw(DEC)
            if draw(st.booleans()):
                b.update(lower=Num("-2.5"), upper=Num("2.5"), initial=Num(f"{draw(st.integers(-2, 2))}.25"))
            b["input"] = pick(t)
        sig[name] = t
        blocks.append(b)
    for b in delays:
        b["input"] = pick(b["type"])
    # a subsystem instantiated twice, read as I.o
    subsystems = {"clamp01": {"inputs": ["u"], "blocks": [
        {"name": "s", "block": "Saturation", "input": "u", "lower": Num("0.0"), "upper": Num("1.0")},
        {"name": "g", "block": "Gain", "input": "s", "gain": draw(DEC)}], "outputs": {"o": "g"}}}
    for k in range(draw(st.integers(0, 2))):
        blocks.append({"name": f"c{k}", "block": "Subsystem", "subsystem": "clamp01", "inputs": [pick("float64")]})
        sig[f"c{k}.o"] = "float64"
    order = draw(st.permutations(blocks))
    used_sub = any(b["block"] == "Subsystem" for b in blocks)
    outports = {"Out1": pick("float64"), "Out2": pick("bool")}
    ctrl = {"name": "C", "inputs": {"name": "C_U", "fields": dict(INPUTS)},
            "outputs": {"name": "C_Y", "fields": {"Out1": "float64", "Out2": "bool"}}}
    if used_sub:
        ctrl["subsystems"] = subsystems
    ctrl.update(blocks=list(order), outports=outports)
    topics = [{"name": f"/in_{n}", "direction": "subscribe", "type": TOPIC_TYPE[q], "queue_size": 1}
              for n, q in INPUTS.items()]
    topics += [{"name": "/out1", "direction": "publish", "type": "std_msgs/Float64", "queue_size": 1},
               {"name": "/out2", "direction": "publish", "type": "std_msgs/Bool", "queue_size": 1}]
    return {"node": {"name": "n", "period_ms": draw(st.integers(1, 1000))}, "controller": ctrl, "topics": topics,
            "relations": {"inputs": [{"topic": f"/in_{n}", "field": "data", "input": n} for n in INPUTS],
                          "outputs": [{"output": "Out1", "topic": "/out1", "field": "data"},
                                      {"output": "Out2", "topic": "/out2", "field": "data"}]}}


@SETTINGS
@given(diagrams())
def test_random_diagrams_read_the_same(model):
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "m.yaml"
        path.write_text(yaml.safe_dump(model, sort_keys=False), encoding="utf-8")
        loaded = load_model(path)   # the generator writes valid diagrams: a refusal fails the test
        assert diagram.diagram_text(path) == diagram_text(loaded), path.read_text()
