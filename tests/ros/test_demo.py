"""The run phase of ``make demo`` (``python -m pyrosgen.ros.demo``) on the
LandShark node built with the example controller: no terminal, the spoofed
GPS is rejected, everything it started is stopped."""

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
