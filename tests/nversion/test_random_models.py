"""Random small models (hypothesis): every one the front end accepts is
read the same by the second reading (``pyrosgen.nversion``): timeouts,
fallbacks of every form (float32 constants rounded once from their
decimal), derived inputs, bounded sequences and strings with their
maxima and policies, arrays of messages and of strings, stamps and
constant strings.  The generator writes models meant to be valid, and
the test requires the front end to accept them, so that the property is
exercised, not assumed."""

from __future__ import annotations

import tempfile
from pathlib import Path

import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pyrosgen.frontend.validate import load_model
from pyrosgen.nversion import reader
from pyrosgen.proof.modeltext import model_text

SETTINGS = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])

DECIMAL = st.builds(lambda s, a, b, e: f"{s}{a}.{b}e{e}" if e else f"{s}{a}.{b}",
                    st.sampled_from(["", "-"]), st.integers(0, 99999), st.integers(0, 999999),
                    st.integers(-40, 30))


@st.composite
def leaf(draw, ty, topic):
    """(field path, derived kind or None, controller type, extra) of a
    topic of type ``ty`` (its ``max_length`` drawn once, in ``topic``)."""
    extra: dict = {}
    maxima = topic.setdefault("max_length", {})

    def mx(key, lo, hi):
        if key not in maxima:
            maxima[key] = draw(st.integers(lo, hi))
        return maxima[key]
    if ty == "std_msgs/Float64":
        return "data", None, "float64", extra
    if ty == "geometry_msgs/TwistStamped":
        return draw(st.sampled_from([("twist.linear.x", None, "float64", extra),
                                     ("twist.angular.z", None, "float64", extra),
                                     ("header.seq", None, "uint32", extra),
                                     ("header.stamp.nsec", None, "uint32", extra)]))
    if ty == "sensor_msgs/LaserScan":
        n = mx("ranges", 1, 1500)
        return draw(st.sampled_from([(f"ranges[{draw(st.integers(0, n - 1))}]", None, "float32", extra),
                                     ("ranges", "length", "uint32", extra),
                                     ("ranges", "truncated", "bool", extra),
                                     ("angle_min", None, "float32", extra),
                                     (f"header.frame_id[{draw(st.integers(0, 19))}]", None, "uint8", extra)]))
    if ty == "nav_msgs/Odometry":
        return draw(st.sampled_from([(f"pose.covariance[{draw(st.integers(0, 35))}]", None, "float64", extra),
                                     ("pose.pose.position.y", None, "float64", extra),
                                     ("child_frame_id", "length", "uint32", extra)]))
    if ty == "sensor_msgs/JointState":
        n, m = mx("name", 1, 8), mx("name[]", 1, 40)
        maxima["position"] = n
        i = draw(st.integers(0, n - 1))
        return draw(st.sampled_from([(f"name[{i}][{draw(st.integers(0, m - 1))}]", None, "uint8", extra),
                                     (f"name[{i}]", "length", "uint32", extra),
                                     (f"position[{i}]", None, "float64", extra),
                                     ("name", "length", "uint32", extra)]))
    n = mx("poses", 1, 6)
    mx("poses[].header.frame_id", 20, 40)
    i = draw(st.integers(0, n - 1))
    return draw(st.sampled_from([(f"poses[{i}].pose.position.x", None, "float64", extra),
                                 (f"poses[{i}].header.frame_id", "length", "uint32", extra),
                                 ("poses", "length", "uint32", extra)]))


SUB_TYPES = ["std_msgs/Float64", "geometry_msgs/TwistStamped", "sensor_msgs/LaserScan", "nav_msgs/Odometry",
             "sensor_msgs/JointState", "nav_msgs/Path"]


@st.composite
def models(draw):
    period = draw(st.integers(1, 200))
    ins: dict[str, str] = {}
    topics, in_rels = [], []
    for k, ty in enumerate(draw(st.lists(st.sampled_from(SUB_TYPES), min_size=1, max_size=3, unique=True))):
        topic = {"name": f"/in{k}", "direction": "subscribe", "type": ty, "queue_size": draw(st.integers(1, 20))}
        timed = draw(st.booleans())
        if timed:
            topic["timeout_ms"] = draw(st.integers(period, 100000))
            topic["on_timeout"] = draw(st.sampled_from(["zero", "hold"]))
        for j in range(draw(st.integers(1, 3))):
            path, derived, ctype, _ = draw(leaf(ty, topic))
            name = f"I{k}_{j}"
            ins[name] = ctype
            row = {"topic": topic["name"], "field": path, "input": name}
            if derived:
                row["derived"] = derived
            elif timed and draw(st.booleans()):
                if ctype in ("float32", "float64"):
                    row["on_timeout"] = draw(st.one_of(st.sampled_from(["hold", "zero"]), DECIMAL.map(Num)))
                elif ctype == "bool":
                    row["on_timeout"] = draw(st.booleans())
                else:
                    row["on_timeout"] = draw(st.integers(0, 255))
            in_rels.append(row)
        if draw(st.booleans()):
            kind = draw(st.sampled_from(["is_new", "received", "age_ms"]))
            name = f"D{k}"
            ins[name] = "uint32" if kind == "age_ms" else "bool"
            in_rels.append({"topic": topic["name"], "derived": kind, "input": name})
        if not topic["max_length"]:
            del topic["max_length"]
        topics.append(topic)
    outs = {"Out0": "float64"}
    pub = {"name": "/cmd", "direction": "publish", "type": "geometry_msgs/TwistStamped", "queue_size": 1}
    if draw(st.booleans()):
        pub["stamp"] = "now"
    if draw(st.booleans()):
        pub["frame_id"] = draw(st.text(st.characters(min_codepoint=32, max_codepoint=126), max_size=20))
    topics.append(pub)
    out_rels = [{"output": "Out0", "topic": "/cmd", "field": draw(st.sampled_from(["twist.linear.x",
                                                                                   "twist.angular.y"]))}]
    if draw(st.booleans()):
        n = draw(st.integers(1, 50))
        topics.append({"name": "/arr", "direction": "publish", "type": "std_msgs/Float32MultiArray",
                       "queue_size": 1, "max_length": {"data": n}})
        outs.update({"E": "float32", "NE": "uint32"})
        out_rels += [{"output": "E", "topic": "/arr", "field": f"data[{draw(st.integers(0, n - 1))}]"},
                     {"output": "NE", "topic": "/arr", "field": "data", "derived": "length"}]
    if "sensor_msgs/LaserScan" in [t["type"] for t in topics] and draw(st.booleans()):
        scan = next(t for t in topics if t["type"] == "sensor_msgs/LaserScan")
        if not any(r.get("derived") == "truncated" for r in in_rels if r["topic"] == scan["name"]) \
                and any("ranges" in r.get("field", "") for r in in_rels if r["topic"] == scan["name"]):
            scan["policy"] = {"ranges": "reject"}
    return {"node": {"name": "n", "period_ms": period},
            "controller": {"name": "C", "inputs": {"name": "C_U", "fields": ins},
                           "outputs": {"name": "C_Y", "fields": outs}},
            "topics": topics, "relations": {"inputs": in_rels, "outputs": out_rels}}


class Num(str):
    """A decimal written as a plain YAML number."""


yaml.SafeDumper.add_representer(Num, lambda d, v: d.represent_scalar("tag:yaml.org,2002:float", str(v)))


@SETTINGS
@given(models())
def test_random_models_read_the_same(model):
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "m.yaml"
        path.write_text(yaml.safe_dump(model, sort_keys=False), encoding="utf-8")
        loaded = load_model(path)   # the generator writes valid models: a refusal fails the test
        assert reader.model_text(path) == model_text(loaded), path.read_text()
