"""Concurrent runs into one output folder install one after the other:
a run waits while another holds the folder, and the folder then holds
one run's complete, consistent set of files."""

from __future__ import annotations

import fcntl
import os
import subprocess
import sys
import time

from support.generate import LANDSHARK, REPO, require_library

NODE = "landshark_controller"


def test_a_run_waits_for_the_folder(tmp_path):
    require_library()
    out = tmp_path / "out"
    out.mkdir()
    fd = os.open(out, os.O_RDONLY | os.O_DIRECTORY)
    fcntl.flock(fd, fcntl.LOCK_EX)  # as another run installing into it
    proc = subprocess.Popen([sys.executable, "-m", "pyrosgen", "generate", str(LANDSHARK), "-o", str(out)],
                            cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            stdin=subprocess.DEVNULL)
    try:
        waited = []
        for line in proc.stderr:
            waited.append(line)
            if "waiting for another pyrosgen run" in line:
                break
        assert any("waiting for another pyrosgen run writing into" in ln for ln in waited), "".join(waited)
        time.sleep(0.5)
        assert proc.poll() is None and list(out.iterdir()) == []  # nothing written while the folder is held
    finally:
        os.close(fd)  # release: the run goes on
        rest_out, rest_err = proc.communicate(timeout=300)
    assert proc.returncode == 0, rest_err
    assert (out / f"{NODE}_glue.c").is_file()
    from pyrosgen.verify.recheck import verify_folder

    assert verify_folder(out).ok


def test_two_runs_at_once_leave_a_consistent_folder(tmp_path):
    """Two models of the same node (periods 20 and 30 ms) generated into
    one folder at the same time: the folder verifies, and its model is one
    of the two, whole."""
    require_library()
    other = tmp_path / "other" / LANDSHARK.name
    other.parent.mkdir()
    other.write_text(LANDSHARK.read_text().replace("period_ms: 20", "period_ms: 30"))
    assert "period_ms: 30" in other.read_text()
    out = tmp_path / "out"
    procs = [subprocess.Popen([sys.executable, "-m", "pyrosgen", "generate", str(m), "-o", str(out), "-q"],
                              cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL)
             for m in (LANDSHARK, other)]
    for p in procs:
        _, err = p.communicate(timeout=300)
        assert p.returncode == 0, err
    from pyrosgen.verify.recheck import verify_folder

    assert verify_folder(out).ok
    text = (out / f"{NODE}.model").read_text()
    assert ("period_ms 20\n" in text) != ("period_ms 30\n" in text)
