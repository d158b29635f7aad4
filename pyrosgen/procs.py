"""Running external tools so that none outlives pyrosgen.

Every tool runs in a session (and process group) of its own, so that an
interrupt, a termination or a timeout of pyrosgen stops the whole tree
the tool started (``g++`` runs ``cc1plus``, ``make`` runs ``coqc``):
:func:`run` sends SIGTERM to the group, then SIGKILL to what is left, and
waits for the leader before it re-raises.  (A signal from the terminal
reaches only pyrosgen, which is in the foreground group; pyrosgen then
stops the tools itself.)  A pyrosgen killed outright (SIGKILL, which
it cannot catch) stops its tools all the same: each is started with the
parent-death signal SIGKILL (Linux's ``PR_SET_PDEATHSIG``), so that no
``coqc`` goes on writing into a folder that a later run reads."""

from __future__ import annotations

import os
import signal
import subprocess
import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path

__all__ = ["run", "start", "Started", "stop_group", "DEFAULT_MAX_MEMORY", "out_of_memory"]

#: The default address-space limit of a tool ``verify`` runs,
#: in bytes: 8 GiB.  ``verify`` of the largest model of BENCHMARKS.md's
#: controller arrays (two arrays of 8,192 elements) passes with every tool
#: limited to 1 GiB (coqc, coqchk, ocamlopt, the printer; the largest
#: resident size 502 MiB) and fails at 0.6 GiB (coqc "Out of memory"):
#: 8 GiB leaves a margin of 8 for larger nodes.
DEFAULT_MAX_MEMORY = 8 << 30


def stop_group(proc: subprocess.Popen, grace: float = 2.0) -> None:
    """SIGTERM to ``proc``'s process group, SIGKILL after ``grace``
    seconds to whatever is still in it; wait for ``proc``."""
    for sig, wait in ((signal.SIGTERM, grace), (signal.SIGKILL, None)):
        try:
            os.killpg(proc.pid, sig)
        except (ProcessLookupError, PermissionError):
            pass
        try:
            proc.wait(timeout=wait)
        except subprocess.TimeoutExpired:
            continue
        if sig == signal.SIGTERM:
            # the leader is gone; members that ignored SIGTERM are not
            try:
                os.killpg(proc.pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass
        return


def _libc_prctl():
    """``prctl`` from the C library, looked up in pyrosgen (not in the
    child between ``fork`` and ``exec``); ``None`` where there is none."""
    import ctypes
    import ctypes.util

    try:
        return ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True).prctl
    except (OSError, AttributeError):
        return None


#: ``PR_SET_PDEATHSIG`` of ``<linux/prctl.h>``
_PR_SET_PDEATHSIG = 1
_PRCTL = _libc_prctl() if os.name == "posix" else None


def _limits(big_stack: bool, max_memory: int | None):
    """What the child runs before the tool (``preexec_fn``): SIGKILL
    asked for when its parent dies (and the tool not started at all if the
    parent is already gone), the stack's soft limit raised to its hard
    limit (``big_stack``), the address space limited to ``max_memory``
    bytes (``RLIMIT_AS``: an allocation beyond it fails in the tool, which
    stops, instead of the machine swapping)."""
    parent = os.getpid()

    def preexec() -> None:
        if _PRCTL is not None:
            _PRCTL(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
            if os.getppid() != parent:   # died before the request took effect
                os._exit(1)
        if not big_stack and max_memory is None:
            return
        import resource

        if big_stack:
            _soft, hard = resource.getrlimit(resource.RLIMIT_STACK)
            resource.setrlimit(resource.RLIMIT_STACK, (hard, hard))
        if max_memory is not None:
            _soft, hard = resource.getrlimit(resource.RLIMIT_AS)
            limit = max_memory if hard == resource.RLIM_INFINITY else min(max_memory, hard)
            resource.setrlimit(resource.RLIMIT_AS, (limit, hard))

    return preexec


def out_of_memory(returncode: int, output: str) -> bool:
    """Whether a tool run under an address-space limit stopped for want of
    memory, as far as its exit shows: OCaml's ``Out of memory`` (coqc,
    coqchk, ocamlopt, the extracted printer), C's ``std::bad_alloc`` or
    ``virtual memory exhausted`` (gcc), ``Cannot allocate memory``, or
    killed by SIGSEGV/SIGABRT/SIGKILL (a failed allocation not checked)."""
    return returncode in (-signal.SIGSEGV, -signal.SIGABRT, -signal.SIGKILL) or any(
        s in output for s in ("Out of memory", "Out_of_memory", "bad_alloc", "memory exhausted",
                              "Cannot allocate memory", "out of memory"))


def run(argv: Sequence[str], *, cwd: str | Path | None = None, timeout: float | None = None,
        env: Mapping[str, str] | None = None, input: str | None = None,
        big_stack: bool = False, max_memory: int | None = None) -> subprocess.CompletedProcess:
    """``subprocess.run(argv, capture_output=True, text=True,
    errors="replace", check=False)`` with standard input from ``input`` (or
    ``/dev/null``), in a process group of its own that is stopped on any
    exception (``KeyboardInterrupt``, ``subprocess.TimeoutExpired``, ...).
    ``big_stack``: the child's stack limit raised to the hard limit (the
    OCaml compilers recurse on the depth of the extracted terms: 8 MB is
    not enough for a diagram of 5,000 blocks, BENCHMARKS.md section 7).
    ``max_memory``: the child's address space limited to that many bytes
    (:func:`out_of_memory` tells whether it ran out)."""
    with subprocess.Popen(
        [str(a) for a in argv], cwd=None if cwd is None else str(cwd), env=None if env is None else dict(env),
        stdin=subprocess.PIPE if input is not None else subprocess.DEVNULL,
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, errors="replace",
        start_new_session=True, preexec_fn=_limits(big_stack, max_memory),
    ) as proc:
        try:
            out, err = proc.communicate(input, timeout=timeout)
        except BaseException:
            stop_group(proc)
            raise
        return subprocess.CompletedProcess(proc.args, proc.returncode, out, err)


class Started:
    """A tool started by :func:`start`, running while pyrosgen goes on.

    :meth:`finish` waits for it and returns what :func:`run` would have;
    :meth:`stop` stops its process group if it still runs.  As a context
    manager, leaving the block stops it (an exception in the block, an
    interrupt: no tool outlives pyrosgen)."""

    def __init__(self, proc: subprocess.Popen, out, err):
        self._proc, self._out, self._err = proc, out, err
        self._done: subprocess.CompletedProcess | None = None

    @property
    def args(self):
        return self._proc.args

    def finish(self, timeout: float | None = None) -> subprocess.CompletedProcess:
        """Wait for the tool (raises ``subprocess.TimeoutExpired`` after
        ``timeout`` seconds, the tool then stopped); its outputs."""
        if self._done is None:
            try:
                self._proc.wait(timeout=timeout)
            except BaseException:
                self.stop()
                raise
            texts = []
            for f in (self._out, self._err):
                f.seek(0)
                texts.append(f.read())
                f.close()
            self._done = subprocess.CompletedProcess(self._proc.args, self._proc.returncode, *texts)
        return self._done

    def stop(self) -> None:
        if self._proc.poll() is None:
            stop_group(self._proc)
        for f in (self._out, self._err):
            if not f.closed:
                f.close()

    def __enter__(self) -> "Started":
        return self

    def __exit__(self, *exc) -> None:
        if self._done is None:
            self.stop()


def start(argv: Sequence[str], *, cwd: str | Path | None = None, max_memory: int | None = None) -> Started:
    """Start ``argv`` as :func:`run` would run it (standard input from
    ``/dev/null``, a process group of its own), its outputs kept in
    temporary files (a pipe nobody reads while pyrosgen does something
    else could fill up and block the tool), and return at once."""
    out = tempfile.TemporaryFile(mode="w+", encoding="utf-8", errors="replace")
    err = tempfile.TemporaryFile(mode="w+", encoding="utf-8", errors="replace")
    try:
        proc = subprocess.Popen(
            [str(a) for a in argv], cwd=None if cwd is None else str(cwd), stdin=subprocess.DEVNULL,
            stdout=out, stderr=err, start_new_session=True, preexec_fn=_limits(False, max_memory),
        )
    except BaseException:
        out.close()
        err.close()
        raise
    return Started(proc, out, err)
