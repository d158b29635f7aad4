"""An rclpy peer for the ROS 2 tests, run with the ROS 2 installation's
interpreter (``.venv-ros2/bin/python peer.py PLAN.json RESULT.json``) in the
environment of :func:`pyrosgen.ros2.env.ros2_env` (loopback discovery, a
domain of the test's own).

The plan: ``publishers`` and ``subscribers`` (topic -> ROS 2 type such as
``geometry_msgs/TwistStamped``), ``match_timeout`` (seconds to wait until
every publisher has a subscription and every listened topic a publisher:
discovery takes 0.2 to 3 s), ``best_effort`` (optional: the publishers
with the best-effort reliability, the others reliable), ``run_anyway``
(optional: run the steps even without the match), and ``steps``:

- ``{"sleep": s}``: listen for ``s`` seconds;
- ``{"publish": {topic: {leaf: value}}}``: one message per topic, the
  leaves given (floats as their IEEE bits), every other leaf zero;
- ``{"stream": {topic: {leaf: value}}, "period": p, "duration": s}``: the
  same every ``p`` seconds for ``s`` seconds, listening in between.

The result: ``matched_after`` (s), the steps with their monotonic start and
end ``t0``/``t1`` and the time of each publication (``published``: [t,
topic]), and ``received``: every message heard, ``[t, topic, leaves]`` (the
floats as IEEE bits).
"""

import importlib
import json
import struct
import sys
import time

import rclpy

_FLOATS = ("float", "double")


def msg_class(ros_type: str):
    pkg, name = ros_type.split("/")
    return getattr(importlib.import_module(f"{pkg}.msg"), name)


def bits(x: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", x))[0]


def value(b: int) -> float:
    return struct.unpack("<d", struct.pack("<Q", b))[0]


def _is_float(typ: str) -> bool:
    base = typ.split("<")[-1].split("[")[0].rstrip(">,0123456789=")
    return base in _FLOATS


def _leaf(v, typ: str):
    if hasattr(v, "get_fields_and_field_types"):
        return leaves(v)
    if isinstance(v, (list, tuple)) or hasattr(v, "tolist"):
        items = v.tolist() if hasattr(v, "tolist") else list(v)
        return [_leaf(x, typ) for x in items]
    return bits(v) if _is_float(typ) else v


def leaves(m, prefix: str = "") -> dict:
    """Every leaf of ``m`` by path; floats as IEEE bits; a sequence or
    array as the list of its elements (messages as their leaves)."""
    out = {}
    for name, typ in m.get_fields_and_field_types().items():
        v = getattr(m, name)
        if hasattr(v, "get_fields_and_field_types"):
            out.update(leaves(v, f"{prefix}{name}."))
        else:
            out[prefix + name] = _leaf(v, typ)
    return out


def build(cls, values: dict):
    """A message of ``cls`` with the leaves ``values`` (floats as IEEE
    bits, a list for a sequence), every other leaf zero."""
    m = cls()
    for path, v in values.items():
        *parents, leaf = path.split(".")
        obj = m
        for p in parents:
            obj = getattr(obj, p)
        typ = obj.get_fields_and_field_types()[leaf]
        if isinstance(v, list):
            v = [value(x) if _is_float(typ) else x for x in v]
        elif _is_float(typ):
            v = value(v)
        setattr(obj, leaf, v)
    return m


def main() -> int:
    plan = json.load(open(sys.argv[1]))
    rclpy.init()
    node = rclpy.create_node("pyrosgen_test_peer")
    best_effort = set(plan.get("best_effort", ()))

    def qos(topic: str):
        from rclpy.qos import QoSProfile, ReliabilityPolicy
        return QoSProfile(depth=10, reliability=ReliabilityPolicy.BEST_EFFORT if topic in best_effort
                          else ReliabilityPolicy.RELIABLE)

    pubs = {t: (node.create_publisher(msg_class(ty), t, qos(t)), msg_class(ty)) for t, ty in plan["publishers"].items()}
    received = []
    for topic, ty in plan["subscribers"].items():
        node.create_subscription(msg_class(ty), topic,
                                 lambda m, topic=topic: received.append([time.monotonic(), topic, leaves(m)]), 10)
    t0 = time.monotonic()
    result = {"matched_after": None, "steps": [], "received": received}
    while time.monotonic() - t0 < plan["match_timeout"]:
        if all(p.get_subscription_count() > 0 for p, _ in pubs.values()) \
                and all(node.count_publishers(t) > 0 for t in plan["subscribers"]):
            result["matched_after"] = time.monotonic() - t0
            break
        rclpy.spin_once(node, timeout_sec=0.05)

    def listen(until: float) -> None:
        while time.monotonic() < until:
            rclpy.spin_once(node, timeout_sec=min(0.01, max(0.0, until - time.monotonic())))

    def publish(msgs: dict, log: list) -> None:
        for topic, values in msgs.items():
            pub, cls = pubs[topic]
            m = build(cls, values)
            log.append([time.monotonic(), topic])
            pub.publish(m)

    if result["matched_after"] is not None or plan.get("run_anyway"):
        for step in plan["steps"]:
            s = {"t0": time.monotonic(), "published": []}
            if "sleep" in step:
                listen(s["t0"] + step["sleep"])
            elif "publish" in step:
                publish(step["publish"], s["published"])
            else:
                end = s["t0"] + step["duration"]
                while time.monotonic() < end:
                    publish(step["stream"], s["published"])
                    listen(min(end, time.monotonic() + step["period"]))
            s["t1"] = time.monotonic()
            result["steps"].append(s)
    node.destroy_node()
    rclpy.shutdown()
    json.dump(result, open(sys.argv[2], "w"))
    return 0 if result["matched_after"] is not None else 3


if __name__ == "__main__":
    sys.exit(main())
