"""The catkin package written by ``pyrosgen build`` for examples/multi (custom
messages: gencpp headers in OUT/include) configures and builds with cmake."""

from __future__ import annotations

import subprocess


def test_multi_catkin_package_builds(multi_echo, tmp_path):
    cml = (multi_echo / "CMakeLists.txt").read_text()
    assert "  include\n" in cml and (multi_echo / "include" / "robot_msgs" / "FusionStatus.h").is_file()
    assert "robot_msgs" not in cml.split("find_package", 1)[1].split(")", 1)[0]  # custom: not a catkin package
    b = tmp_path / "cmake"
    r = subprocess.run(["cmake", "-S", str(multi_echo), "-B", str(b), "-DPYTHON_EXECUTABLE=/usr/bin/python3"],
                       capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=300)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    r = subprocess.run(["make", "-C", str(b)], capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=600)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    assert (b / "devel" / "lib" / "multi_node" / "multi_node").is_file()
