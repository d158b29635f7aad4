"""Files that are not regular files (a FIFO, a device, a directory named
like a file) are refused before a byte is read: ``check`` never waits for
a FIFO's writer. Run in a subprocess with a timeout, so that a regression
fails instead of hanging the suite."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
LANDSHARK = ROOT / "examples/landshark/landshark_controller.yaml"

MODEL = """node: {name: big, period_ms: 10}
controller:
  name: C
  inputs: {name: C_U, fields: {In1: float64}}
  outputs: {name: C_Y, fields: {Out1: float64}}
msg_paths: [msg]
topics:
  - {name: /big, direction: subscribe, type: big_msgs/Big, queue_size: 1}
  - {name: /out, direction: publish, type: std_msgs/Float64, queue_size: 1}
relations:
  inputs:
    - {topic: /big, field: x, input: In1}
  outputs:
    - {output: Out1, topic: /out, field: data}
"""


def _check(path: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "pyrosgen", "check", str(path)], cwd=ROOT, capture_output=True,
                          text=True, stdin=subprocess.DEVNULL, timeout=60)


def test_fifo_in_msg_paths(tmp_path):
    (tmp_path / "msg" / "big_msgs" / "msg").mkdir(parents=True)
    os.mkfifo(tmp_path / "msg" / "big_msgs" / "msg" / "Big.msg")
    (tmp_path / "m.yaml").write_text(MODEL)
    r = _check(tmp_path / "m.yaml")
    assert r.returncode == 1
    assert "Big.msg: error: cannot read message definition: it is a FIFO, not a regular file [rule 4.5]" in r.stderr


def test_directory_named_like_a_message(tmp_path):
    (tmp_path / "msg" / "big_msgs" / "msg" / "Big.msg").mkdir(parents=True)
    (tmp_path / "m.yaml").write_text(MODEL)
    r = _check(tmp_path / "m.yaml")
    assert r.returncode == 1 and "Traceback" not in r.stderr


def test_model_file_that_is_a_device(tmp_path):
    """A model named by the user may be a pipe (check /dev/stdin, tested in
    test_cli.py); a device is read up to the size limit, then refused."""
    r = _check(Path("/dev/zero"))
    assert r.returncode == 1 and "too large" in r.stderr and "Traceback" not in r.stderr
