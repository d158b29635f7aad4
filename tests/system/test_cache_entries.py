"""The cache's entries on their own (``pyrosgen.system.generate``): an
entry is renamed into place only when complete, so a writer killed in the
middle (SIGKILL: no ``finally`` runs) or failing leaves nothing under the
key that a reader trusts, and the next run removes its temporary folder
(its ``flock`` died with it); a folder still locked by a live writer is
left alone.  (``test_generate.py`` kills a whole ``system generate``.)"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

from pyrosgen.system.generate import _clean_dead_temps, _put_entry, entry_valid

KEY = "k" * 64

WRITER = """\
import sys, time
from pathlib import Path
from pyrosgen.system.generate import _put_entry

def fill(tmp):
    (tmp / "files").mkdir()
    (tmp / "files" / "half.v").write_text("(* half written *)")
    (Path(sys.argv[2]) / "ready").write_text("")
    time.sleep(600)
    return ("ok", 0.0, 0, [])

_put_entry(Path(sys.argv[1]), sys.argv[3], fill)
"""


def _writer(cache: Path, flag: Path) -> subprocess.Popen:
    proc = subprocess.Popen([sys.executable, "-c", WRITER, str(cache), str(flag), KEY], start_new_session=True)
    deadline = time.monotonic() + 60
    while not (flag / "ready").exists():
        assert time.monotonic() < deadline and proc.poll() is None, "the writer did not start"
        time.sleep(0.05)
    return proc


def test_a_killed_writer_leaves_nothing_trusted(tmp_path):
    cache, flag = tmp_path / "cache", tmp_path / "flag"
    cache.mkdir()
    flag.mkdir()
    proc = _writer(cache, flag)
    try:
        temps = [p for p in cache.iterdir() if p.name.startswith(".tmp-")]
        assert len(temps) == 1 and (temps[0] / "files" / "half.v").is_file()
        # a live writer's folder is not removed by another run
        _clean_dead_temps(cache)
        assert temps[0].exists()
        os.killpg(proc.pid, signal.SIGKILL)
    finally:
        proc.wait(timeout=60)
    assert proc.returncode == -signal.SIGKILL
    assert not (cache / KEY).exists() and not entry_valid(cache / KEY, KEY)
    _clean_dead_temps(cache)
    assert list(cache.iterdir()) == []


def test_a_failing_fill_installs_nothing(tmp_path):
    def fill(tmp):
        (tmp / "files").mkdir()
        (tmp / "files" / "x.v").write_text("x")
        return ("error", 0.0, 2, ["pyrosgen: error: it failed"])

    status = _put_entry(tmp_path, KEY, fill)
    assert status[0] == "error" and list(tmp_path.iterdir()) == []


def test_a_complete_entry_is_trusted_and_a_changed_one_is_not(tmp_path):
    def fill(tmp):
        (tmp / "files").mkdir()
        (tmp / "files" / "x.v").write_text("x")
        return ("ok", 0.0, 0, [])

    assert _put_entry(tmp_path, KEY, fill)[0] == "ok"
    assert entry_valid(tmp_path / KEY, KEY)
    assert not entry_valid(tmp_path / KEY, "j" * 64)          # another key
    (tmp_path / KEY / "files" / "extra.v").write_text("y")     # a file added
    assert not entry_valid(tmp_path / KEY, KEY)


def test_one_coqchk_for_several_modules_names_the_rejected_one(tmp_path):
    """The run's new node modules are re-checked by one coqchk
    (:meth:`CoqDriver.coqchk_many`): it accepts closed modules, and when it
    rejects the batch, the error names the module that uses an axiom."""
    import pytest

    from pyrosgen.proof.coqdriver import CoqDriver, CoqError

    (tmp_path / "Good.v").write_text("Definition x := 1.\nTheorem t : x = 1. Proof. reflexivity. Qed.\n")
    (tmp_path / "Bad.v").write_text("Ax" + "iom cheat : False.\nTheorem u : 1 = 2. Proof. destruct cheat. Qed.\n")
    for f in ("Good.v", "Bad.v"):
        subprocess.run(["coqc", "-R", str(tmp_path), "L", f], cwd=tmp_path, check=True, capture_output=True)
    drv = CoqDriver()
    lib = (tmp_path, "L")
    assert drv.coqchk_many(["L.Good"], lib).ok
    with pytest.raises(CoqError) as e:
        drv.coqchk_many(["L.Good", "L.Bad"], lib)
    assert "L.Bad" in e.value.summary and "L.Good" not in e.value.summary
    assert any("L.Bad.cheat" in line for line in e.value.lines), e.value.lines


def test_two_modules_of_one_name_are_both_checked(tmp_path):
    """A node model run with two controller folders is two keys and one
    module name: each of its modules is re-checked (two batches), so a bad
    second one is refused, not hidden under the first's name."""
    import pytest

    from pyrosgen.proof.coqdriver import CoqError
    from pyrosgen.system.generate import _check_pending

    texts = {"k1": "Definition x := 1.\n", "k2": "Ax" + "iom cheat : False.\nDefinition x := 1.\n"}
    for key, text in texts.items():
        d = tmp_path / "pending" / key / "coq"
        d.mkdir(parents=True)
        (d / "A.v").write_text(text)
        subprocess.run(["coqc", "-R", str(d), "RosgenNode", "A.v"], cwd=d, check=True, capture_output=True)
    _check_pending(tmp_path / "pending", [("k1", "A")], tmp_path / "w1")
    with pytest.raises(CoqError) as e:
        _check_pending(tmp_path / "pending", [("k1", "A"), ("k2", "A")], tmp_path / "w2")
    assert "RosgenNode.A" in e.value.summary
    assert sorted(p.name for p in (tmp_path / "w2").iterdir()) == ["0", "1"]


def test_a_lockless_folder_of_a_dead_writer_is_removed_and_a_live_ones_kept(tmp_path):
    """A writer killed between creating its folder and locking it leaves a
    folder without ``.lock``: removed at once when the pid in its name no
    longer runs, kept (until it is ten minutes old) while it does."""
    gone = subprocess.Popen([sys.executable, "-c", "pass"])
    gone.wait(timeout=60)
    dead = tmp_path / f".tmp-{gone.pid}-abc"
    live = tmp_path / f".tmp-{os.getpid()}-def"
    for d in (dead, live):
        (d / "files").mkdir(parents=True)
        (d / "files" / "half.v").write_text("(* half written *)")
    _clean_dead_temps(tmp_path)
    assert not dead.exists()
    assert (live / "files" / "half.v").is_file()
