"""SIGTERM and SIGHUP stop pyrosgen as Ctrl-C does: exit 130, the work
folder removed, nothing written, and no tool it started left running
(the compiler's ``cc1plus``, stood for here by a fake compiler's child;
``coqc``): tools run in process groups of
their own, which pyrosgen stops (pyrosgen/procs.py)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from .conftest import LANDSHARK, LANDSHARK_CTL, ROOT


def _processes_mentioning(text: str) -> list[str]:
    found = []
    for d in Path("/proc").iterdir():
        if not d.name.isdigit():
            continue
        try:
            cmd = (d / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
        except OSError:
            continue
        if text in cmd:
            found.append(f"{d.name}: {cmd[:200]}")
    return found


def _stop_at(argv: list[str], marker: str, sig: int, tmp_path: Path, until: Path | None = None) -> tuple[int, str]:
    proc = subprocess.Popen([sys.executable, "-m", "pyrosgen", *argv], cwd=ROOT, stdin=subprocess.DEVNULL,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    seen = []
    try:
        for line in proc.stderr:
            seen.append(line)
            if marker in line:
                break
        assert any(marker in ln for ln in seen), "".join(seen)
        for _ in range(100):
            if until is None or until.is_file():
                break
            time.sleep(0.1)
        time.sleep(0.3)  # the tool is running now
        assert _processes_mentioning(str(tmp_path)), "the tool did not start"
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    return proc.returncode, "".join(seen) + err


FAKE_CXX = """#!/bin/sh
# g++, except that compiling the wrapper starts a long grandchild (as
# g++ starts cc1plus) and waits for it
case "$*" in
  *_ros.cpp*) sleep 600 & echo $! > "{pidfile}"; wait; exit 1 ;;
esac
exec g++ "$@"
"""


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP], ids=["SIGTERM", "SIGHUP"])
def test_signal_during_the_wrapper_compile(tmp_path, sig, monkeypatch):
    work = tmp_path / "w"
    work.mkdir()
    pidfile = tmp_path / "grandchild.pid"
    cxx = tmp_path / "fake-g++"
    cxx.write_text(FAKE_CXX.format(pidfile=pidfile))
    cxx.chmod(0o755)
    monkeypatch.setenv("CXX", str(cxx))
    out = work / "out"
    code, err = _stop_at(["build", str(LANDSHARK), "--controller", str(LANDSHARK_CTL), "-o", str(out)],
                         "compile wrapper:", sig, work, until=pidfile)
    assert code == 130, err
    assert "pyrosgen: interrupted" in err
    grandchild = int(pidfile.read_text())
    time.sleep(0.5)
    state = Path(f"/proc/{grandchild}/stat")
    assert not state.exists() or state.read_text().split(") ")[1].startswith("Z"), "the compiler's child survived"
    assert _processes_mentioning(str(work)) == []
    assert not out.exists()
    assert [p.name for p in work.iterdir()] == []  # no work folder


def test_sighup_during_coqc(tmp_path):
    out = tmp_path / "out"
    code, err = _stop_at(["generate", str(LANDSHARK), "-o", str(out)], "[2/5] coqc", signal.SIGHUP, tmp_path)
    assert code == 130, err
    time.sleep(0.5)
    assert _processes_mentioning(str(tmp_path)) == []
    assert [p.name for p in tmp_path.iterdir()] == []


def test_tools_may_get_the_hard_stack_limit():
    """procs.run(big_stack=True) (the OCaml compilers, on the deep terms of
    a 5,000-block diagram) raises the child's stack limit to the hard one;
    without it the child keeps the soft limit."""
    import resource

    from pyrosgen import procs

    soft, hard = resource.getrlimit(resource.RLIMIT_STACK)
    show = ["sh", "-c", "ulimit -s"]
    def kib(n):
        return "unlimited" if n == resource.RLIM_INFINITY else str(n // 1024)
    assert procs.run(show, big_stack=True).stdout.strip() == kib(hard)
    assert procs.run(show).stdout.strip() == kib(soft)
