"""Every message type the front end accepts builds: one node with one
topic of each standard ROS 1 message package (ONE build for all of them),
whose C++ headers ``make deps`` installs."""

from __future__ import annotations

import subprocess

import yaml

from pyrosgen.frontend.msgdeb import DEBIAN_DEV

from .conftest import ROOT, pyrosgen

MODEL = ROOT / "tests" / "support" / "all_packages" / "all_packages.yaml"
CTL = ROOT / "tests" / "support" / "all_packages" / "controller"


def test_one_node_uses_every_standard_message_package(tmp_path):
    topics = yaml.safe_load(MODEL.read_text())["topics"]
    used = {t["type"].split("/")[0] for t in topics}
    assert used == set(DEBIAN_DEV), sorted(set(DEBIAN_DEV) ^ used)
    out = tmp_path / "out"
    run = pyrosgen("build", MODEL, "--controller", CTL, "-o", out, "-q")
    assert run.returncode == 0, run.stderr
    assert (out / "bin" / "all_packages").is_file()
    text = (out / "all_packages_ros.cpp").read_text()
    for t in topics:
        assert f"#include <{t['type']}.h>" in text, t["type"]
    # the catkin package configures (package.xml lists each package once)
    r = subprocess.run(["cmake", "-S", str(out / "all_packages"), "-B", str(tmp_path / "cmake"),
                        "-DPYTHON_EXECUTABLE=/usr/bin/python3"],
                       capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=300)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    run = pyrosgen("check", MODEL)
    assert run.returncode == 0 and "note:" not in run.stderr, run.stderr
