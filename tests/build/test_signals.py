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


@pytest.mark.parametrize("how", ["run", "start"])
def test_tools_die_with_a_killed_pyrosgen(tmp_path, how):
    """A pyrosgen killed by SIGKILL (which it cannot catch) leaves no tool
    running: procs.run and procs.start ask for the parent-death signal
    SIGKILL, although each tool has a session of its own."""
    mark = tmp_path / "tool-ran"
    tool = [sys.executable, "-c",
            f"import pathlib, os, time; pathlib.Path({str(mark)!r}).write_text(str(os.getpid())); time.sleep(120)"]
    body = ("import sys, time; from pyrosgen import procs; "
            + ("procs.run(sys.argv[1:], timeout=300)" if how == "run"
               else "s = procs.start(sys.argv[1:]); time.sleep(300)"))
    parent = subprocess.Popen([sys.executable, "-c", body, *tool], cwd=ROOT, start_new_session=True)
    tool_pid = None
    try:
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline and not (mark.exists() and mark.read_text()):
            time.sleep(0.05)
        tool_pid = int(mark.read_text())
        os.kill(parent.pid, signal.SIGKILL)   # the parent only: the tool is in a session of its own
        parent.wait(timeout=30)
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and Path(f"/proc/{tool_pid}").exists() \
                and "zombie" not in Path(f"/proc/{tool_pid}/status").read_text(errors="replace"):
            time.sleep(0.05)
        alive = Path(f"/proc/{tool_pid}").exists() and \
            "zombie" not in Path(f"/proc/{tool_pid}/status").read_text(errors="replace")
        assert not alive, f"tool {tool_pid} outlived its killed parent"
    finally:
        if parent.poll() is None:
            parent.kill()
            parent.wait()
        if tool_pid is not None:
            try:
                os.kill(tool_pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
