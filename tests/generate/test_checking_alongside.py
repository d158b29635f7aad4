"""``pyrosgen generate`` runs ``coqchk`` alongside the printing (step 3 in
the background while step 4 runs): what it decides still decides the run,
nothing is written unless both succeed, and no ``coqchk`` outlives the
run, whatever ends it.

The tools are real except ``coqchk``, which these tests replace by a
command of their own (through ``CoqDriver._coqchk_argv``) so that it fails,
or runs longer than the printing, on demand; the real ``coqchk`` is run
by every other generate test."""

from __future__ import annotations

import os
import time

import pytest

from pyrosgen import procs
from pyrosgen.generate import generate
from pyrosgen.proof.coqdriver import CoqDriver, CoqError

from support.generate import LANDSHARK, require_library


@pytest.fixture
def started(monkeypatch):
    """Every process :func:`procs.start` starts, as (Popen, Started)."""
    seen = []
    orig = procs.start

    def spy(argv, **kw):
        s = orig(argv, **kw)
        seen.append(s)
        return s

    monkeypatch.setattr(procs, "start", spy)
    return seen


def _fake_coqchk(monkeypatch, script: str) -> None:
    monkeypatch.setattr(CoqDriver, "_coqchk_argv", lambda self, module, lib, vm: ["sh", "-c", script])


def _gone(s: procs.Started, within: float = 5.0) -> bool:
    """The process and its group have ended (a member the leader left
    behind is reaped by init: allow it ``within`` seconds)."""
    if s._proc.poll() is None:
        return False
    deadline = time.monotonic() + within
    while True:
        try:
            os.killpg(s._proc.pid, 0)
        except ProcessLookupError:
            return True
        if time.monotonic() > deadline:
            return False
        time.sleep(0.05)


def test_a_coqchk_rejection_fails_the_run_and_writes_nothing(tmp_path, monkeypatch, started):
    require_library()
    _fake_coqchk(monkeypatch, "echo 'Error: the module does not type check' >&2; exit 1")
    out = tmp_path / "out"
    with pytest.raises(CoqError) as exc:
        generate(LANDSHARK, out)
    assert "coqchk rejected RosgenNode.landshark_controller (exit status 1)" in str(exc.value)
    assert any("does not type check" in ln for ln in exc.value.lines)
    assert not out.exists() and not list(tmp_path.glob(".pyrosgen-*"))
    assert len(started) == 1 and _gone(started[0])


def test_the_run_waits_for_a_coqchk_slower_than_the_printing(tmp_path, monkeypatch, started):
    """A verdict that comes after the printing is waited for: a slow
    rejection still fails the run (nothing written)."""
    require_library()
    _fake_coqchk(monkeypatch, "sleep 2; echo 'Error: late' >&2; exit 3")
    out = tmp_path / "out"
    with pytest.raises(CoqError, match=r"coqchk rejected .* \(exit status 3\)"):
        generate(LANDSHARK, out)
    assert not out.exists()
    assert _gone(started[0])


def test_coqchk_s_verdict_comes_before_a_printing_failure(tmp_path, monkeypatch, started):
    """Both fail: the error reported is coqchk's (step 3), not the
    printer's (step 4); with coqchk fine, it is the printer's."""
    require_library()

    def broken_printer(self, *a, **kw):
        raise CoqError("the extracted printer failed (exit status 9)")

    monkeypatch.setattr(CoqDriver, "print_texts", broken_printer)
    _fake_coqchk(monkeypatch, "sleep 0.5; exit 1")
    with pytest.raises(CoqError, match="coqchk rejected"):
        generate(LANDSHARK, tmp_path / "a")
    _fake_coqchk(monkeypatch, "sleep 0.5; exit 0")
    with pytest.raises(CoqError, match="the extracted printer failed"):
        generate(LANDSHARK, tmp_path / "b")
    assert not (tmp_path / "a").exists() and not (tmp_path / "b").exists()
    assert len(started) == 2 and all(_gone(s) for s in started)


def test_an_interrupt_while_printing_stops_coqchk(tmp_path, monkeypatch, started):
    """Ctrl-C during the printing: the run stops at once (it does not wait
    for a coqchk of 60 s) and coqchk, with its process group, is gone."""
    require_library()

    def interrupted(self, *a, **kw):
        raise KeyboardInterrupt

    monkeypatch.setattr(CoqDriver, "print_texts", interrupted)
    _fake_coqchk(monkeypatch, "sleep 60 & sleep 60; wait")
    t0 = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        generate(LANDSHARK, tmp_path / "out")
    assert time.monotonic() - t0 < 30
    assert len(started) == 1 and _gone(started[0])
    assert not (tmp_path / "out").exists() and not list(tmp_path.glob(".pyrosgen-*"))


def test_started_returns_the_outputs_and_respects_its_timeout(tmp_path):
    """procs.start: the outputs of a tool that wrote more than a pipe
    holds while nobody read them; a timeout stops the tool."""
    s = procs.start(["sh", "-c", "head -c 300000 /dev/zero | tr '\\0' x; echo err >&2; exit 4"], cwd=tmp_path)
    time.sleep(0.5)
    res = s.finish(timeout=30)
    assert res.returncode == 4 and len(res.stdout) == 300000 and res.stderr == "err\n"
    slow = procs.start(["sleep", "60"])
    with pytest.raises(Exception) as exc:
        slow.finish(timeout=0.2)
    assert type(exc.value).__name__ == "TimeoutExpired" and _gone(slow)
