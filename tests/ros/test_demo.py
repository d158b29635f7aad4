"""The run phases of ``make demo``: ``python -m pyrosgen.ros.demo`` on the
LandShark node built with the example controller (the spoofed GPS is
rejected) and ``python -m pyrosgen.ros.demo_guard`` on the velocity guard
(each silent command source is replaced once its timeout passed, the
robot stops); no terminal, everything they started is stopped; bad usage
is an error (exit 1, no traceback)."""

from __future__ import annotations

import re
import subprocess
import sys

from support import ros as rosutil


def test_demo_runs_without_a_terminal(landshark_real, tmp_path):
    env = {"CI": "true", "PATH": "/usr/bin:/bin", "HOME": str(tmp_path)}
    r = subprocess.run([sys.executable, "-m", "pyrosgen.ros.demo", str(landshark_real), "--duration", "7", "--spoof", "3:6"],
                       cwd=rosutil.ROOT, env=env, stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    out = r.stdout
    assert "sim: OK: the spoofed GPS was rejected" in out
    rows = [line.split() for line in out.splitlines() if re.match(r"^\s*\d+\.\d\d\s", line)]
    assert len(rows) >= 12
    spoofed = [row for row in rows if "SPOOFED" in row]
    assert spoofed and all(float(row[3]) > 2.5 for row in spoofed)      # the GPS lies
    assert all(0.85 <= float(row[5]) <= 1.15 for row in spoofed)       # the command does not follow
    pids = [int(p) for p in re.findall(r"\(pid (\d+)\)", out)]
    assert len(pids) == 3 and not any(rosutil.alive(p) for p in pids)
    assert "demo: all processes stopped" in out


def test_guard_demo_shows_the_timeouts(velocity_guard_node, tmp_path):
    env = {"CI": "true", "PATH": "/usr/bin:/bin", "HOME": str(tmp_path)}
    r = subprocess.run([sys.executable, "-m", "pyrosgen.ros.demo_guard", str(velocity_guard_node),
                        "--teleop-stop", "1.5", "--nav-stop", "3", "--duration", "4"],
                       cwd=rosutil.ROOT, env=env, stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    out = r.stdout
    assert "sources: OK: each silent source was replaced once its timeout passed, and the robot stops" in out
    # the command before and after each source stopped, in order
    changes = re.findall(r"command changed to\s+(\S+)\s+(\S+)\s+(\S+)", out)
    assert [c[2] for c in changes] == ["teleop's", "nav's", "zero"], changes
    lates = [int(m) for m in re.findall(r"became \S+ (\d+) ms after (?:teleop|nav)'s last message", out)]
    assert len(lates) == 2 and all(ms >= 500 for ms in lates), lates     # never before the timeout
    rows = [ln.split() for ln in out.splitlines() if re.match(r"^\s*\d+\.\d\d\s+(on|off)\s", ln)]
    assert any(row[1:3] == ["off", "on"] and row[3:5] == ["2.00", "0.20"] for row in rows)
    assert rows[-1][1:3] == ["off", "off"] and rows[-1][3:5] == ["0.00", "0.00"]
    pids = [int(p) for p in re.findall(r"\(pid (\d+)\)", out)]
    assert len(pids) == 3 and not any(rosutil.alive(p) for p in pids)
    assert "demo: all processes stopped" in out


def test_guard_demo_bad_usage(tmp_path):
    env = {"CI": "true", "PATH": "/usr/bin:/bin", "HOME": str(tmp_path)}
    for args, msg in ((["--teleop-stop", "5", "--nav-stop", "3"], "need 0 < --teleop-stop < --nav-stop < --duration"),
                      (["--duration", "x"], "invalid float value: 'x'")):
        r = subprocess.run([sys.executable, "-m", "pyrosgen.ros.demo_guard", str(tmp_path), *args],
                           cwd=rosutil.ROOT, env=env, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                           timeout=60)
        assert r.returncode == 1 and msg in r.stderr and "Traceback" not in r.stderr, r.stderr
    r = subprocess.run([sys.executable, "-m", "pyrosgen.ros.demo_guard", str(tmp_path / "nothing")],
                       cwd=rosutil.ROOT, env=env, stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=60)
    assert r.returncode == 1 and "not found: run pyrosgen build" in r.stdout and "Traceback" not in r.stderr
