"""Fixtures for the real-ROS tests: a private rosmaster per test on
127.0.0.1 at a free port, stopped (with every process the test spawned
through it) even when the test fails; the PID of each is recorded in
``rosutil.STARTED`` (checked by ``test_leftovers.py`` and at the end of the session by ``tests/conftest.py``).

Nodes are built once per session (``pyrosgen.ros.build``) and shared."""

from __future__ import annotations

import shutil
import textwrap
from pathlib import Path

import pytest

from pyrosgen.ros.build import build, pkg_config
from pyrosgen.generate import generate_model
from pyrosgen.frontend.validate import load_model
from pyrosgen.ros.rosmaster import free_port
from pyrosgen.ros import wrapper as rosgen

from support import ros as rosutil
from support.ros import ROUNDTRIP_TYPES, RecordingRosEnv


@pytest.fixture
def ros(tmp_path):
    home = tmp_path / "ros"
    (home / "log").mkdir(parents=True, exist_ok=True)
    env = RecordingRosEnv(port=free_port(), home=home)
    try:
        env.start_master()
        yield env
    finally:
        env.close()


@pytest.fixture(scope="session")
def nodes_dir(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("nodes")


@pytest.fixture(scope="session")
def landshark_echo(nodes_dir) -> Path:
    """The LandShark node with the bit-exact test controller: its OUT."""
    out = nodes_dir / "landshark_echo"
    build(rosutil.LANDSHARK, rosutil.CONTROLLERS / "landshark_echo", out)
    return out


@pytest.fixture(scope="session")
def landshark_real(nodes_dir, landshark_echo) -> Path:
    """The LandShark node with the example (median + PI) controller; built
    from a copy of the echo build, so that the wrapper object is reused."""
    out = nodes_dir / "landshark_real"
    shutil.copytree(landshark_echo, out)
    res = build(rosutil.LANDSHARK, rosutil.LANDSHARK_CTL, out)
    assert dict(res.steps)["obj/landshark_controller_ros.o"] is False  # reused
    return out


@pytest.fixture(scope="session")
def velocity_guard_node(nodes_dir) -> Path:
    """examples/velocity_guard built (timed topics, rule 4.12; the
    controller C from its block diagram): the output folder."""
    out = nodes_dir / "velocity_guard"
    build(rosutil.ROOT / "examples" / "velocity_guard" / "velocity_guard.yaml", None, out)
    assert (out / "bin" / "velocity_guard").is_file()
    return out


@pytest.fixture(scope="session")
def multi_echo(nodes_dir) -> Path:
    """examples/multi with the bit-exact test controller: its OUT."""
    out = nodes_dir / "multi_echo"
    build(rosutil.MULTI, rosutil.CONTROLLERS / "multi_echo", out)
    return out


@pytest.fixture(scope="session")
def roundtrip(nodes_dir):
    """The echo harness linked with the wrapper generated for a test model
    that subscribes ``/rt/in_<x>`` and publishes ``/rt/out_<x>`` for each
    message type: ``(binary, model)``."""
    d = nodes_dir / "roundtrip"
    d.mkdir()
    topics = []
    for short, t in ROUNDTRIP_TYPES.items():
        topics.append(f"  - {{name: /rt/in_{short}, direction: subscribe, type: {t}, queue_size: 1000}}")
        topics.append(f"  - {{name: /rt/out_{short}, direction: publish, type: {t}, queue_size: 1000}}")
    (d / "rt_node.yaml").write_text(textwrap.dedent("""\
        node: {name: rt_node, period_ms: 10}
        controller:
          name: Echo
          inputs: {name: Echo_U, fields: {A: float64}}
          outputs: {name: Echo_Y, fields: {B: float64}}
        topics:
        """) + "\n".join(topics) + textwrap.dedent(f"""
        relations:
          inputs: [{{topic: /rt/in_twist, field: linear.x, input: A}}]
          outputs: [{{output: B, topic: /rt/out_twist, field: linear.x}}]
        msg_paths: [{rosutil.MULTI_MSG}]
        """))
    model = load_model(d / "rt_node.yaml")
    gen = d / "gen"
    generate_model(model, gen)
    for name, text in rosgen.render_wrapper(model).items():
        (gen / name).write_text(text)
    rosgen.generate_custom_cpp(model, gen / "include")
    pairs = [(f"/rt/in_{s}", f"/rt/out_{s}") for s in ROUNDTRIP_TYPES]
    (gen / "harness.c").write_text(rosutil.echo_harness(model, pairs))
    cflags, libs = pkg_config(rosgen.ros_pkg_config_modules(model))
    import subprocess

    def run(argv):
        r = subprocess.run(argv, cwd=gen, capture_output=True, text=True)
        assert r.returncode == 0, f"{' '.join(argv)}:\n{r.stderr}"

    run(["gcc", "-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic", "-I", ".", "-c", "harness.c", "-o", "harness.o"])
    run(["g++", "-std=c++14", "-O2", "-Wall", "-Wextra", "-Werror", "-pthread", "-I", ".", "-I", "include", *cflags,
         "-c", "rt_node_ros.cpp", "-o", "rt_node_ros.o"])
    run(["g++", "-pthread", "harness.o", "rt_node_ros.o", "-o", "rt_echo", *libs])
    return gen / "rt_echo", model
