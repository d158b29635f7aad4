"""The rclpy side of bench/ros2.py, run with .venv-ros2/bin/python in the
environment of pyrosgen.ros2.env.ros2_env.

usage: ros2_latency_peer.py ROUNDS [landshark | scan_guard]

Waits for the discovery match, then ``rounds`` times:
- landshark (default): publishes one value on LandShark's three inputs and
  measures the time from the first publication to the first base velocity
  that the echo controller computed from all three (its twin below);
- scan_guard: publishes a sensor_msgs/LaserScan of 1,081 ranges, all
  5.0 m but index 540 (in the front sector), a value new each round, and
  measures the time to the first /closest (std_msgs/Float32) equal to it
  (the scan guard's controller reports the closest valid range of the
  sector);
with a pause of 20 to 40 ms (random) between rounds.  Prints JSON: the
latencies in ms."""

import json
import random
import struct
import sys
import time

import rclpy
from geometry_msgs.msg import TwistStamped
from sensor_msgs.msg import LaserScan
from std_msgs.msg import Float32

INS = ("/landshark/left_wheel_velocity", "/landshark/right_wheel_velocity", "/landshark/gps_velocity")
OUT = "/landshark_control/base_velocity"
M64 = (1 << 64) - 1


def bits(x):
    return struct.unpack("<Q", struct.pack("<d", x))[0]


def rotl(b, n):
    return ((b << n) | (b >> (64 - n))) & M64


def echo(b):  # tests/ros/controllers/landshark_echo with In1 = In2 = In3
    return (b ^ rotl(b, 21) ^ rotl(b, 42) ^ 0x3FF0000000000000) & M64


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def wait_match(node, pubs, out):
    t0 = time.monotonic()
    while not (all(p.get_subscription_count() for p in pubs) and node.count_publishers(out)):
        rclpy.spin_once(node, timeout_sec=0.05)
        if time.monotonic() - t0 > 20:
            sys.exit("no discovery match within 20 s")


def pause(node, rng):
    end = time.monotonic() + rng.uniform(0.02, 0.04)
    while time.monotonic() < end:
        rclpy.spin_once(node, timeout_sec=0.005)


def scan_guard(node, rounds, rng):
    pub = node.create_publisher(LaserScan, "/scan", 10)
    heard = []
    node.create_subscription(Float32, "/closest", lambda m: heard.append((time.monotonic(), m.data)), 10)
    wait_match(node, [pub], "/closest")
    lat = []
    m = LaserScan()
    m.header.frame_id = "laser"
    m.angle_min, m.angle_max, m.angle_increment = -2.35619449, 2.35619449, 0.00436332313
    m.scan_time, m.range_min, m.range_max = 0.025, 0.05, 30.0
    ranges = [5.0] * 1081
    for i in range(rounds):
        want = f32(2.0 + (i % 512) / 256.0)
        ranges[540] = want
        m.ranges = ranges
        heard.clear()
        t_pub = time.monotonic()
        pub.publish(m)
        while time.monotonic() - t_pub < 1.0 and not any(v == want for _, v in heard):
            rclpy.spin_once(node, timeout_sec=0.001)
        hit = [t for t, v in heard if v == want]
        if hit:
            lat.append((hit[0] - t_pub) * 1000.0)
        pause(node, rng)
    return lat


def main():
    rounds = int(sys.argv[1])
    which = sys.argv[2] if len(sys.argv) > 2 else "landshark"
    rng = random.Random(31)
    rclpy.init()
    node = rclpy.create_node("pyrosgen_bench_peer")
    if which == "scan_guard":
        lat = scan_guard(node, rounds, rng)
        node.destroy_node()
        rclpy.shutdown()
        print(json.dumps({"latency_ms": lat, "rounds": rounds}))
        return
    pubs = [node.create_publisher(TwistStamped, t, 10) for t in INS]
    heard = []
    node.create_subscription(TwistStamped, OUT, lambda m: heard.append((time.monotonic(), bits(m.twist.linear.x))), 10)
    wait_match(node, pubs, OUT)
    lat = []
    for i in range(rounds):
        v = 1.0 + i / 1000.0
        want = echo(bits(v))
        heard.clear()
        m = TwistStamped()
        m.twist.linear.x = v
        t_pub = time.monotonic()
        for p in pubs:
            p.publish(m)
        while time.monotonic() - t_pub < 1.0 and not any(b == want for _, b in heard):
            rclpy.spin_once(node, timeout_sec=0.001)
        hit = [t for t, b in heard if b == want]
        if hit:
            lat.append((hit[0] - t_pub) * 1000.0)
        pause(node, rng)
    node.destroy_node()
    rclpy.shutdown()
    print(json.dumps({"latency_ms": lat, "rounds": rounds, "matched_after_s": None}))


if __name__ == "__main__":
    main()
