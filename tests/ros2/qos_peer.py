"""An rclpy peer with a QoS of its choosing, for the QoS tests (rule 4.18,
tests/ros2/test_qos_ros2.py), run with the ROS 2 installation's interpreter
(``python qos_peer.py PLAN.json RESULT.json``) in the environment of
:func:`pyrosgen.ros2.env.ros2_env`.

The plan: ``publishers`` and ``subscribers``, lists of ``{"topic", "qos"}``
(``qos``: ``{"reliability": "reliable" | "best_effort", "durability":
"volatile" | "transient_local", "depth": N}``, or ``"sensor_data"`` for
rclpy's ``qos_profile_sensor_data``); a publisher has a ``value`` (a
``std_msgs/Float64``'s data) and ``once`` (publish it once, at the start,
else every ``period`` seconds); a subscriber has ``start_after`` (seconds
before it is created: a late joiner); ``duration`` (seconds the peer runs
at most); ``until`` (optional: ``{topic: n}``, the peer stops as soon as it
received at least ``n`` messages on each of these topics: discovery takes
0.2 to 3 s, more on a loaded machine).

The result: ``received``: ``[topic, data, source_timestamp,
received_timestamp]`` per message (the timestamps of rclpy's message info,
ns), ``incompatible``: the incompatible-QoS events the peer's publishers and
subscriptions saw, ``[topic, side, total_count]``, and ``published``: how
many messages each publisher sent.
"""

import json
import sys
import time

import rclpy
from rclpy.event_handler import PublisherEventCallbacks, SubscriptionEventCallbacks
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy, qos_profile_sensor_data
from std_msgs.msg import Float64


def profile(q):
    if q == "sensor_data":
        return qos_profile_sensor_data
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=q.get("depth", 10),
                      reliability={"reliable": ReliabilityPolicy.RELIABLE,
                                   "best_effort": ReliabilityPolicy.BEST_EFFORT}[q.get("reliability", "reliable")],
                      durability={"volatile": DurabilityPolicy.VOLATILE,
                                  "transient_local": DurabilityPolicy.TRANSIENT_LOCAL}[q.get("durability", "volatile")])


def main() -> int:
    plan = json.load(open(sys.argv[1]))
    rclpy.init()
    node = rclpy.create_node("pyrosgen_qos_peer")
    received, incompatible, published = [], [], {}

    def on_incompatible(topic, side):
        return lambda info: incompatible.append([topic, side, info.total_count])

    pubs = []
    for p in plan.get("publishers", []):
        pub = node.create_publisher(Float64, p["topic"], profile(p["qos"]), event_callbacks=PublisherEventCallbacks(
            incompatible_qos=on_incompatible(p["topic"], "publisher")))
        pubs.append((p, pub))
        published[p["topic"]] = 0

    def publish(p, pub):
        pub.publish(Float64(data=float(p["value"])))
        published[p["topic"]] += 1

    for p, pub in pubs:
        if p.get("once"):
            publish(p, pub)
    pending = sorted(plan.get("subscribers", []), key=lambda s: s.get("start_after", 0.0))
    t0 = time.monotonic()
    next_pub = t0
    period = plan.get("period", 0.05)
    until = plan.get("until", {})

    def done() -> bool:
        if not until:
            return False
        counts = {}
        for r in received:
            counts[r[0]] = counts.get(r[0], 0) + 1
        return all(counts.get(t, 0) >= n for t, n in until.items())

    while time.monotonic() - t0 < plan["duration"] and not done():
        while pending and time.monotonic() - t0 >= pending[0].get("start_after", 0.0):
            s = pending.pop(0)
            topic = s["topic"]
            node.create_subscription(
                Float64, topic,
                lambda m, info, topic=topic: received.append(
                    [topic, m.data, info["source_timestamp"], info["received_timestamp"]]),
                profile(s["qos"]),
                event_callbacks=SubscriptionEventCallbacks(incompatible_qos=on_incompatible(topic, "subscription")))
        if time.monotonic() >= next_pub:
            for p, pub in pubs:
                if not p.get("once"):
                    publish(p, pub)
            next_pub += period
        rclpy.spin_once(node, timeout_sec=0.005)
    node.destroy_node()
    rclpy.shutdown()
    json.dump({"received": received, "incompatible": incompatible, "published": published}, open(sys.argv[2], "w"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
