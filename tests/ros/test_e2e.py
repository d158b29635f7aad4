"""End to end on a real master: built nodes (glue proved by Coq, wrapper,
controller) driven by rospy; every published field is checked bit for bit
against the model's relations and the controller."""

from __future__ import annotations

import ctypes
import random
import subprocess

from pyrosgen.frontend.validate import load_model

from support import expect
from support import ros as rosutil
from support.ros import dbits, received, run_driver, start_node

LEFT, RIGHT, GPS = "/landshark/left_wheel_velocity", "/landshark/right_wheel_velocity", "/landshark/gps_velocity"
BASE = "/landshark_control/base_velocity"
TS = "geometry_msgs/TwistStamped"


def _plan_rounds(model, rounds, zero_phase: float, settle: float, msg_paths=None):
    """Publishers for every subscribed topic, subscribers for every published
    one; a zero phase, then each round publishes one message per subscribed
    topic and waits ``settle`` seconds."""
    steps = [{"sleep": zero_phase}]
    for msgs in rounds:
        for topic, values in msgs.items():
            steps.append({"publish": {"topic": topic, "values": values, "fill_noncarried": True}})
        steps.append({"sleep": settle})
    return {
        "msg_paths": msg_paths or {},
        "publishers": [{"topic": t.name, "type": t.msg_type} for t in model.subscribed],
        "subscribers": [{"topic": t.name, "type": t.msg_type} for t in model.published],
        "wait_messages": True,
        "steps": steps,
    }


def _check_rounds(model, result, rounds, controller, settle_margin: float):
    """Outputs received before the first publication answer all-zero inputs;
    outputs received in the second part of each round's wait answer the
    newest messages."""
    problems = []
    first_publish = result["steps"][1]["t0"]
    zero_y = controller(expect.zero_inputs(model))
    n_zero = 0
    for t in model.published:
        before = received(result, t.name, None, first_publish)
        n_zero += len(before)
        for r in before:
            problems += [f"before any input, {t.name}: {p}" for p in expect.check_published(model, t.name, zero_y, r["leaves"])]
    assert n_zero >= 5 * len(model.published), f"too few outputs before any input: {n_zero}"
    last: dict = {}
    k = 1
    for i, msgs in enumerate(rounds):
        last.update(msgs)
        k += len(msgs)
        wait = result["steps"][k]
        k += 1
        y = controller(expect.inputs_from(model, last))
        for t in model.published:
            window = received(result, t.name, wait["t0"] + settle_margin, wait["t1"])
            assert len(window) >= 5, f"round {i}: only {len(window)} messages on {t.name}"
            for r in window:
                problems += [f"round {i}, {t.name}: {p}" for p in expect.check_published(model, t.name, y, r["leaves"])]
    assert not problems, "\n".join(problems[:40])


def test_landshark_end_to_end_bit_exact(ros, landshark_echo, tmp_path):
    model = load_model(rosutil.LANDSHARK)
    rng = random.Random(20240501)
    modes = ["special", "random", "min", "max", "special", "random", "special", "zero"]
    rounds = [{t.name: expect.random_message(model, TS, rng, m) for t in model.subscribed} for m in modes]
    start_node(ros, landshark_echo / "bin" / "landshark_controller", tmp_path / "node.log")
    result = run_driver(ros, _plan_rounds(model, rounds, zero_phase=0.6, settle=0.6), tmp_path)
    _check_rounds(model, result, rounds, expect.landshark_echo, settle_margin=0.3)


def test_multi_end_to_end_bit_exact(ros, multi_echo, tmp_path):
    model = load_model(rosutil.MULTI)
    rng = random.Random(7)
    modes = ["random", "special", "max", "min", "random", "special"]
    rounds = [{t.name: expect.random_message(model, t.msg_type, rng, m) for t in model.subscribed} for m in modes]
    # one round where only some topics change: the others keep their last message
    rounds.append({"/imu/data": expect.random_message(model, "sensor_msgs/Imu", rng, "random")})
    start_node(ros, multi_echo / "bin" / "multi_node", tmp_path / "node.log")
    plan = _plan_rounds(model, rounds, zero_phase=0.6, settle=0.6, msg_paths=rosutil.CUSTOM_MSG_PATHS)
    result = run_driver(ros, plan, tmp_path)
    _check_rounds(model, result, rounds, expect.multi_echo, settle_margin=0.3)


def _controller_lib(tmp_path):
    """examples/landshark/controller/Controller.c as a shared library,
    compiled with the flags pyrosgen build uses for controller code."""
    from pyrosgen.ros.build import CONTROLLER_CFLAGS

    lib = tmp_path / "libcontroller.so"
    subprocess.run(["gcc", *CONTROLLER_CFLAGS, "-fPIC", "-shared", "-I", str(rosutil.LANDSHARK_CTL),
                    str(rosutil.LANDSHARK_CTL / "Controller.c"), "-o", str(lib)], check=True)
    return ctypes.CDLL(str(lib))


def _steady_output(lib, inputs, steps=2000) -> int:
    class U(ctypes.Structure):
        _fields_ = [("In1", ctypes.c_double), ("In2", ctypes.c_double), ("In3", ctypes.c_double)]

    u = U.in_dll(lib, "Controller_U")
    y = ctypes.c_double.in_dll(lib, "Controller_Y")
    lib.Controller_initialize()
    for _ in range(steps):
        u.In1, u.In2, u.In3 = inputs
        lib.Controller_step()
    return dbits(y.value)


def test_landshark_real_controller_steady_state(ros, landshark_real, tmp_path):
    """The example controller (median of three + PI): with steady readings,
    one of them a spoofed GPS at 3x the wheel speed, the command settles on
    the value the controller computes for the median, bit for bit (computed
    by the same C code through ctypes), which is the command for an honest
    GPS, and far from the command a mean-based estimate would give."""
    lib = _controller_lib(tmp_path)
    left, right, gps = 1.4, 1.5, 4.5
    expected = _steady_output(lib, (left, right, gps))
    assert expected == _steady_output(lib, (left, right, 1.55))        # honest GPS: same command
    assert expected != _steady_output(lib, ((left + right + gps) / 3,) * 3)  # a mean would differ
    start_node(ros, landshark_real / "bin" / "landshark_controller", tmp_path / "node.log")
    # the integrator goes from +0.5 to its bound -0.5 in 200 steps (4 s)
    rosutil.landshark_settles_on(ros, tmp_path, (left, right, gps), expected, settle=6.0)
