"""Shared helpers of the benchmarks: timed subprocesses (wall, CPU and peak
memory of each child, from ``os.wait4``), the machine description, the
load average, and the private copy of the Coq library the benchmarks run
against (so that other people's rebuilds of ``coq/`` cannot change it in
the middle of a run)."""

from __future__ import annotations

import datetime
import hashlib
import json
import os
import platform
import re
import shutil
import signal
import subprocess
import time
from dataclasses import asdict, dataclass
from pathlib import Path

BENCH = Path(__file__).resolve().parent
REPO = BENCH.parent
RESULTS = BENCH / "results"
#: Scratch space (git-ignored: under build/).
WORK = REPO / "build" / "bench"
PY = REPO / ".venv" / "bin" / "python"
PYROSGEN = REPO / ".venv" / "bin" / "pyrosgen"


def loadavg() -> str:
    """The first three fields of ``/proc/loadavg`` (1, 5, 15 min)."""
    try:
        return " ".join(Path("/proc/loadavg").read_text().split()[:3])
    except OSError:
        return "?"


@dataclass
class Proc:
    """One finished child process."""

    argv: list[str]
    rc: int
    wall: float      #: seconds
    user: float      #: seconds of user CPU (the child and its waited-for children)
    sys: float       #: seconds of system CPU
    maxrss_kb: int   #: peak resident set of the largest process waited for
    stdout: str
    stderr: str

    @property
    def cpu(self) -> float:
        return self.user + self.sys


def run(argv: list[str], *, cwd: Path | None = None, env: dict | None = None,
        timeout: float | None = None, check: bool = True) -> Proc:
    """Run ``argv`` to completion (in its own process group); wall time,
    and CPU and peak memory from the kernel's accounting of that child and
    its waited-for descendants (``wait4``)."""
    import tempfile

    with tempfile.TemporaryFile("w+", errors="replace") as fo, \
            tempfile.TemporaryFile("w+", errors="replace") as fe:
        t0 = time.monotonic()
        p = subprocess.Popen([str(a) for a in argv], cwd=cwd, env=env, stdout=fo, stderr=fe,
                             stdin=subprocess.DEVNULL, start_new_session=True)
        while True:
            pid, status, ru = os.wait4(p.pid, os.WNOHANG)
            if pid == p.pid:
                break
            if timeout is not None and time.monotonic() - t0 > timeout:
                os.killpg(p.pid, signal.SIGKILL)
                os.wait4(p.pid, 0)
                p.returncode = -9
                raise TimeoutError(f"timed out after {timeout} s: {' '.join(map(str, argv))}")
            time.sleep(0.005)
        wall = time.monotonic() - t0
        rc = os.waitstatus_to_exitcode(status)
        p.returncode = rc
        fo.seek(0)
        fe.seek(0)
        out, err = fo.read(), fe.read()
    proc = Proc([str(a) for a in argv], rc, wall, ru.ru_utime, ru.ru_stime, ru.ru_maxrss, out, err)
    if check and rc != 0:
        raise RuntimeError(f"command failed ({rc}): {' '.join(proc.argv)}\n{out[-3000:]}\n{err[-3000:]}")
    return proc


def time_wrap(argv: list[str], out_file: Path) -> list[str]:
    """``argv`` under ``/usr/bin/time`` writing ``wall user sys maxrss_kb``."""
    return ["/usr/bin/time", "-o", str(out_file), "-f", "%e %U %S %M", *argv]


def read_time_file(path: Path) -> tuple[float, float, float, int]:
    """The last line of a :func:`time_wrap` output file."""
    lines = [ln for ln in path.read_text().splitlines() if re.match(r"^[\d.]+ [\d.]+ [\d.]+ \d+$", ln)]
    w, u, s, m = lines[-1].split()
    return float(w), float(u), float(s), int(m)


def first_line(argv: list[str]) -> str:
    try:
        out = subprocess.run(argv, capture_output=True, text=True, check=False)
        return (out.stdout or out.stderr).strip().splitlines()[0]
    except (OSError, IndexError):
        return "?"


def machine() -> dict:
    """CPU model, cores, RAM, load, tool versions, date."""
    cpu = "?"
    try:
        for ln in Path("/proc/cpuinfo").read_text().splitlines():
            if ln.startswith("model name"):
                cpu = ln.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem_gb = "?"
    try:
        for ln in Path("/proc/meminfo").read_text().splitlines():
            if ln.startswith("MemTotal"):
                mem_gb = f"{int(ln.split()[1]) / 1024 / 1024:.1f} GiB"
    except OSError:
        pass
    os_name = "?"
    try:
        for ln in Path("/etc/os-release").read_text().splitlines():
            if ln.startswith("PRETTY_NAME="):
                os_name = ln.split("=", 1)[1].strip('"')
    except OSError:
        pass
    return {
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "cpu": cpu,
        "cores": os.cpu_count(),
        "ram": mem_gb,
        "os": os_name,
        "kernel": platform.release(),
        "python": platform.python_version(),
        "coq": first_line(["coqc", "--version"]).replace("The Coq Proof Assistant, ", "Coq "),
        "ocaml": first_line(["ocamlopt", "-version"]),
        "gcc": first_line(["gcc", "--version"]),
        "g++": first_line(["g++", "--version"]),
        "valgrind": first_line(["valgrind", "--version"]),
        "load_at_start": loadavg(),
    }


# ---------------------------------------------------------------------------
# The private copy of the Coq library

COQ_FILES = ("_CoqProject", "Makefile", "theories", "checks", "tests")


def coq_sources_digest(coq_dir: Path) -> str:
    """Digest of the library's sources (``_CoqProject``, ``Makefile``, and
    every ``.v`` under theories/, checks/, tests/)."""
    h = hashlib.sha256()
    for name in ("_CoqProject", "Makefile"):
        p = coq_dir / name
        if p.is_file():
            h.update(name.encode() + b"\0" + p.read_bytes())
    for sub in ("theories", "checks", "tests"):
        for p in sorted((coq_dir / sub).glob("*.v")):
            h.update(f"{sub}/{p.name}".encode() + b"\0" + p.read_bytes())
    return h.hexdigest()


def copy_coq_sources(dest: Path) -> Path:
    """A fresh copy of ``coq/``'s sources (no build product) in ``dest``."""
    if dest.exists():
        shutil.rmtree(dest)
    dest.mkdir(parents=True)
    src = REPO / "coq"
    for name in COQ_FILES:
        s = src / name
        if s.is_dir():
            shutil.copytree(s, dest / name, ignore=shutil.ignore_patterns(
                "*.vo", "*.vos", "*.vok", "*.glob", ".*.aux", "*.cm*", "*.o"))
        elif s.is_file():
            shutil.copy2(s, dest / name)
    (dest / ".bench-digest").write_text(coq_sources_digest(dest))
    return dest


def private_coq_is_current(dest: Path) -> bool:
    """Whether ``dest`` holds a complete build of the current sources."""
    stamp = dest / ".bench-built"
    if not stamp.is_file():
        return False
    return stamp.read_text().strip() == coq_sources_digest(REPO / "coq")


def use_results(folder: Path) -> None:
    """Write and read results in ``folder`` from now on (--quick runs use
    a scratch folder, so that they do not replace the recorded results)."""
    global RESULTS
    RESULTS = folder


def results_dir() -> Path:
    return RESULTS


def save_json(name: str, data) -> Path:
    RESULTS.mkdir(parents=True, exist_ok=True)
    p = RESULTS / name
    p.write_text(json.dumps(data, indent=1, default=lambda o: asdict(o) if hasattr(o, "__dataclass_fields__") else str(o)) + "\n")
    return p


def load_json(name: str):
    p = RESULTS / name
    return json.loads(p.read_text()) if p.is_file() else None


def median(xs: list[float]) -> float:
    s = sorted(xs)
    n = len(s)
    if n == 0:
        return float("nan")
    return s[n // 2] if n % 2 else (s[n // 2 - 1] + s[n // 2]) / 2
