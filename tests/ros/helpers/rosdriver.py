#!/usr/bin/python3
"""A scripted rospy peer for the real-ROS tests (run by Debian's /usr/bin/python3).

    /usr/bin/python3 rosdriver.py PLAN.json RESULT.json

PLAN (JSON):
  msg_paths:   {"robot_msgs": "/abs/folder/of/robot_msgs/msg", ...} custom packages
  publishers:  [{"topic", "type", "queue_size"?}]
  subscribers: [{"topic", "type", "record"?: "leaves" | "elements" | "deep" | "time"}]
  connect_timeout: seconds to wait until every publisher has a subscriber and
               every subscriber a publisher (the node under test)
  wait_messages: also wait for one message on every subscriber before the steps
  steps: a list of
    {"publish": {"topic", "values": {leaf path: value}, "fill_noncarried": bool}}
    {"sleep": seconds}
    {"flood": {"messages": {topic: values}, "rate": Hz per topic, "duration": s}}
    {"wait_count": {"topic", "count", "timeout"}}
  linger: seconds to keep receiving after the last step

Values: "d:<16 hex digits>" is a float64 by its bits, "f:<8 hex digits>" a
float32 by its bits, integers and booleans as JSON, a variable-length array
of primitives or strings as a JSON list; {"elems": n} gives a variable-length
array of messages n default elements (``poses``), whose leaves are then set
by index (``poses[1].pose.position.x``).  Leaf paths are written
like pyrosgen's FieldPath (``pose.covariance[35]``, ``header.stamp.sec``).

Published messages are sent exactly as given: rospy's habit of overwriting
``header.seq`` with its own counter is switched off (``_has_header``).

RESULT (JSON): {"t_ready", "steps": [{"t0", "t1"}], "received": [{"topic",
"t", "leaves"?}], "published": n, "error"?}.  Every leaf of a received message
is listed: floats by their bits ("d:"/"f:"), integers, strings as
{"str": s}, variable-length arrays as {"var": length}; with "record":
"elements", a variable-length array of primitives also lists each element
as a leaf ("data[0]", ...); with "record": "deep", every variable-length
array does, an array of messages its elements' leaves ("poses[0].pose.
position.x"), an array of strings its strings ("name[0]": {"str": s}).
"""

import json
import re
import struct
import sys
import threading
import time
import traceback

import genpy
import genpy.dynamic
import rospy

_ARRAY = re.compile(r"^([^\[]+)(?:\[(\d*)\])?$")
_FLOAT64 = "float64"
_FLOAT32 = "float32"
_INTS = {"int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64", "byte", "char"}
_CLASSES = {}


def load_class(type_name, msg_paths):
    """The genpy class of ``pkg/Type``: installed, or built from a custom .msg."""
    if type_name in _CLASSES:
        return _CLASSES[type_name]
    pkg, name = type_name.split("/")
    if pkg in msg_paths:
        import genmsg
        import genmsg.msg_loader

        ctx = genmsg.MsgContext.create_default()
        search = {p: [d] for p, d in msg_paths.items()}
        import glob
        import os

        for d in glob.glob("/usr/share/*_msgs/msg"):
            search.setdefault(os.path.basename(os.path.dirname(d)), []).append(d)
        spec = genmsg.msg_loader.load_msg_by_type(ctx, type_name, search)
        genmsg.msg_loader.load_depends(ctx, spec, search)
        full = genmsg.compute_full_text(ctx, spec)
        classes = genpy.dynamic.generate_dynamic(type_name, full)
        _CLASSES.update(classes)
        return classes[type_name]
    mod = __import__(pkg + ".msg", fromlist=[name])
    cls = getattr(mod, name)
    _CLASSES[type_name] = cls
    return cls


def float_bits(kind, value):
    if kind == _FLOAT64:
        return "d:%016x" % struct.unpack("<Q", struct.pack("<d", value))[0]
    return "f:%08x" % struct.unpack("<I", struct.pack("<f", value))[0]


def decode(value):
    if isinstance(value, str) and value.startswith("d:"):
        return struct.unpack("<d", struct.pack("<Q", int(value[2:], 16)))[0]
    if isinstance(value, str) and value.startswith("f:"):
        return struct.unpack("<f", struct.pack("<I", int(value[2:], 16)))[0]
    return value


def flatten(obj, slot_type, path, out, msg_paths, elements=False):
    m = _ARRAY.match(slot_type)
    base, n = m.group(1), m.group(2)
    if n is not None:
        if n == "":
            out[path] = {"var": len(obj)}
            prim = base in (_FLOAT64, _FLOAT32, "bool") or base in _INTS
            if (elements and prim) or elements == "deep":
                for i in range(len(obj)):
                    flatten(obj[i], base, "%s[%d]" % (path, i), out, msg_paths, elements)
            return
        for i in range(int(n)):
            flatten(obj[i], base, "%s[%d]" % (path, i), out, msg_paths, elements)
        return
    if base in ("time", "duration"):
        out[path + ".sec"] = obj.secs
        out[path + ".nsec"] = obj.nsecs
    elif base == "string":
        out[path] = {"str": obj}
    elif base in (_FLOAT64, _FLOAT32):
        out[path] = float_bits(base, obj)
    elif base == "bool":
        out[path] = int(obj)
    elif base in _INTS:
        out[path] = obj if isinstance(obj, int) else ord(obj)
    else:
        if base == "Header":
            base = "std_msgs/Header"
        for name, t in zip(obj.__slots__, obj._slot_types):
            flatten(getattr(obj, name), t, (path + "." if path else "") + name, out, msg_paths, elements)


def leaves(msg, msg_paths, elements=False):
    out = {}
    for name, t in zip(msg.__slots__, msg._slot_types):
        flatten(getattr(msg, name), t, name, out, msg_paths, elements)
    return out


def fill_noncarried(obj, msg_paths):
    """Non-empty strings and variable-length arrays everywhere."""
    for name, t in zip(obj.__slots__, obj._slot_types):
        m = _ARRAY.match(t)
        base, n = m.group(1), m.group(2)
        if n == "":
            if base in ("uint8", "char"):
                setattr(obj, name, b"\x01\x02\x03")
            elif base in (_FLOAT64, _FLOAT32):
                setattr(obj, name, [1.5, -2.5])
            elif base in _INTS:
                setattr(obj, name, [1, 2, 3])
            elif base == "bool":
                setattr(obj, name, [True, False])
            elif base == "string":
                setattr(obj, name, ["a", "bc"])
            elif base in ("time", "duration"):
                setattr(obj, name, [genpy.Time(1, 2)] if base == "time" else [genpy.Duration(1, 2)])
            else:
                if base == "Header":
                    base = "std_msgs/Header"
                setattr(obj, name, [load_class(base, msg_paths)()])
        elif base == "string":
            if n is None:
                setattr(obj, name, "not carried: " + name)
            else:
                setattr(obj, name, ["x"] * int(n))
        elif n is None and "/" in base or base == "Header":
            fill_noncarried(getattr(obj, name), msg_paths)
        elif n is not None and ("/" in base):
            for e in getattr(obj, name):
                fill_noncarried(e, msg_paths)


_STEP = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)(?:\[(\d+)\])?")


def set_leaf(msg, path, value):
    parts = path.split(".")
    obj = msg
    for k, part in enumerate(parts):
        m = _STEP.fullmatch(part)
        name, idx = m.group(1), m.group(2)
        last = k == len(parts) - 1
        if name in ("sec", "nsec") and isinstance(obj, genpy.rostime.TVal):
            setattr(obj, name + "s", int(value))
            return
        if idx is None:
            if last and isinstance(value, dict) and "elems" in value:
                # a variable-length array of messages: that many default elements
                base = obj._slot_types[obj.__slots__.index(name)].split("[", 1)[0]
                cls = load_class("std_msgs/Header" if base == "Header" else base, {})
                setattr(obj, name, [cls() for _ in range(int(value["elems"]))])
            elif last:
                setattr(obj, name, decode(value))
            else:
                obj = getattr(obj, name)
        else:
            arr = getattr(obj, name)
            i = int(idx)
            if last:
                if isinstance(arr, (bytes, tuple)):
                    arr = list(arr)
                arr[i] = decode(value)
                setattr(obj, name, arr)
            else:
                obj = arr[i]


def raw_class(cls):
    """``cls`` without rospy's header.seq rewriting."""
    return type("Raw" + cls.__name__, (cls,), {"_has_header": False})


def build_message(cls, spec, msg_paths):
    msg = cls()
    if spec.get("fill_noncarried"):
        fill_noncarried(msg, msg_paths)
    for path, value in spec.get("values", {}).items():
        set_leaf(msg, path, value)
    return msg


def main():
    plan = json.load(open(sys.argv[1]))
    result = {"received": [], "steps": [], "published": 0}
    lock = threading.Lock()
    msg_paths = plan.get("msg_paths", {})
    try:
        rospy.init_node(plan.get("node_name", "pyrosgen_test_driver"), anonymous=True, disable_signals=True)
        pubs, classes = {}, {}
        for p in plan.get("publishers", []):
            cls = load_class(p["type"], msg_paths)
            classes[p["topic"]] = raw_class(cls)
            pubs[p["topic"]] = rospy.Publisher(p["topic"], classes[p["topic"]], queue_size=p.get("queue_size", 100))
        subs = []
        for s in plan.get("subscribers", []):
            cls = load_class(s["type"], msg_paths)
            mode = s.get("record", "leaves")

            def cb(msg, topic=s["topic"], mode=mode):
                t = time.monotonic()
                item = {"topic": topic, "t": t}
                if mode in ("leaves", "elements", "deep"):
                    item["leaves"] = leaves(msg, msg_paths, "deep" if mode == "deep" else mode == "elements")
                with lock:
                    result["received"].append(item)

            subs.append(rospy.Subscriber(s["topic"], cls, cb, queue_size=10000))
        deadline = time.monotonic() + plan.get("connect_timeout", 30)
        while time.monotonic() < deadline:
            if all(p.get_num_connections() > 0 for p in pubs.values()) and \
               all(s.get_num_connections() > 0 for s in subs):
                break
            time.sleep(0.02)
        else:
            raise RuntimeError("not connected within %s s: publishers %s, subscribers %s" % (
                plan.get("connect_timeout", 30),
                {t: p.get_num_connections() for t, p in pubs.items()},
                {s.name: s.get_num_connections() for s in subs}))
        if plan.get("wait_messages"):
            while time.monotonic() < deadline:
                with lock:
                    seen = {r["topic"] for r in result["received"]}
                if all(s.name in seen for s in subs):
                    break
                time.sleep(0.01)
            else:
                raise RuntimeError("no message on some subscribed topic")
        result["t_ready"] = time.monotonic()
        for step in plan.get("steps", []):
            t0 = time.monotonic()
            if "publish" in step:
                spec = step["publish"]
                pubs[spec["topic"]].publish(build_message(classes[spec["topic"]], spec, msg_paths))
                result["published"] += 1
            elif "sleep" in step:
                time.sleep(step["sleep"])
            elif "flood" in step:
                spec = step["flood"]
                msgs = {t: build_message(classes[t], {"values": v}, msg_paths) for t, v in spec["messages"].items()}
                period = 1.0 / spec["rate"]
                end = t0 + spec["duration"]
                k = 0
                while True:
                    now = time.monotonic()
                    if now >= end:
                        break
                    for t, m in msgs.items():
                        pubs[t].publish(m)
                        result["published"] += 1
                    k += 1
                    wait = t0 + k * period - time.monotonic()
                    if wait > 0:
                        time.sleep(wait)
            elif "wait_count" in step:
                spec = step["wait_count"]
                end = t0 + spec.get("timeout", 10)
                while time.monotonic() < end:
                    with lock:
                        n = sum(1 for r in result["received"] if r["topic"] == spec["topic"])
                    if n >= spec["count"]:
                        break
                    time.sleep(0.01)
            result["steps"].append({"t0": t0, "t1": time.monotonic()})
        time.sleep(plan.get("linger", 0))
    except Exception:  # reported to the test, which fails with it
        result["error"] = traceback.format_exc()
    with lock:
        json.dump(result, open(sys.argv[2], "w"))
    rospy.signal_shutdown("done")


if __name__ == "__main__":
    main()
