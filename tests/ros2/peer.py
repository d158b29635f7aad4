"""An rclpy peer for the ROS 2 tests, run with the ROS 2 installation's
interpreter (``.venv-ros2/bin/python peer.py PLAN.json RESULT.json``) in the
environment of :func:`pyrosgen.ros2.env.ros2_env` (loopback discovery, a
domain of the test's own).

The plan: ``publishers`` (topics of geometry_msgs/TwistStamped the peer
publishes), ``subscriber`` (the topic it listens to), ``match_timeout``
(seconds to wait until every publisher has a subscription and the listened
topic a publisher: discovery takes 0.2 to 3 s), ``steps``: ``{"sleep": s}``
or ``{"publish": {topic: float64 bits of twist.linear.x}}``.  The result:
``matched_after`` (s), the steps with their monotonic start/end ``t0``/``t1``,
and ``received``: every message heard, ``[t, leaves]`` with each leaf of
the TwistStamped (the floats as IEEE bits).
"""

import json
import struct
import sys
import time

import rclpy
from geometry_msgs.msg import TwistStamped


def bits(x: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", x))[0]


def value(b: int) -> float:
    return struct.unpack("<d", struct.pack("<Q", b))[0]


def leaves(m: TwistStamped) -> dict:
    out = {"header.stamp.sec": m.header.stamp.sec, "header.stamp.nanosec": m.header.stamp.nanosec,
           "header.frame_id": m.header.frame_id}
    for part in ("linear", "angular"):
        for axis in "xyz":
            out[f"twist.{part}.{axis}"] = bits(getattr(getattr(m.twist, part), axis))
    return out


def main() -> int:
    plan = json.load(open(sys.argv[1]))
    rclpy.init()
    node = rclpy.create_node("pyrosgen_test_peer")
    pubs = {t: node.create_publisher(TwistStamped, t, 10) for t in plan["publishers"]}
    received = []
    node.create_subscription(TwistStamped, plan["subscriber"],
                             lambda m: received.append([time.monotonic(), leaves(m)]), 10)
    t0 = time.monotonic()
    result = {"matched_after": None, "steps": [], "received": received}
    while time.monotonic() - t0 < plan["match_timeout"]:
        if all(p.get_subscription_count() > 0 for p in pubs.values()) \
                and node.count_publishers(plan["subscriber"]) > 0:
            result["matched_after"] = time.monotonic() - t0
            break
        rclpy.spin_once(node, timeout_sec=0.05)
    if result["matched_after"] is not None:
        for step in plan["steps"]:
            s = {"t0": time.monotonic()}
            if "sleep" in step:
                end = s["t0"] + step["sleep"]
                while time.monotonic() < end:
                    rclpy.spin_once(node, timeout_sec=0.01)
            else:
                for topic, b in step["publish"].items():
                    m = TwistStamped()
                    m.twist.linear.x = value(b)
                    pubs[topic].publish(m)
            s["t1"] = time.monotonic()
            result["steps"].append(s)
    node.destroy_node()
    rclpy.shutdown()
    json.dump(result, open(sys.argv[2], "w"))
    return 0 if result["matched_after"] is not None else 3


if __name__ == "__main__":
    sys.exit(main())
