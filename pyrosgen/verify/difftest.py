"""Differential testing: the Coq semantics against the gcc-compiled C.

The semantics of ``coq/theories/clight/Semantics.v`` and ``coq/theories/clight/Environment.v`` is trusted to describe what
the C glue does once compiled.  This module checks it on concrete runs:
the same message schedule is run

- by the **C side**: the printed glue, compiled by gcc together with a fake
  ROS C API and a test controller (``pyrosgen/templates/difftest_ros.c.j2``,
  generated from the AST dump: structs, subscriptions, publications), which
  reads the schedule on stdin and prints the trace;
- by the **Coq side**: ``Interp.run_program`` (proved sound with respect to
  the semantics, theorem T5) on the node's ``the_program``, extracted to
  OCaml (``coq/templates/difftest.v.j2``) and driven by
  ``pyrosgen/templates/difftest_runner.ml.j2``, which builds the
  ``ros_context`` of the schedule and prints the trace in the same format.

A message of the schedule is the ROS message as it was sent: in each
bounded sequence or string (rules 4.14, 4.15: a struct ``ros_seq_<T>_<N>``
or ``ros_string<N>`` of ``len``, ``truncated`` and ``data[N]``), ``len``
is the real length, ``data`` its first ``N`` elements and anything past
the length.  The Coq side delivers it converted, as the environment
model says (``Environment.delivered``, ``clamp``); the C side converts it
with a C clamp that does what the wrapper's conversion does
(:data:`CLAMPS`: ``len = min(len, N)``, ``truncated = len > N``, the
elements past the new length zero) before calling the callback.  A
message holding a bounded sequence or string of policy reject
(``ros_rseq_<T>_<N>``, ``ros_rstring<N>``) longer than ``N`` is dropped
after the queue: the Coq side by ``Environment.accepted``, the C side by
the test the wrapper makes first thing in its callback (``len > N``:
the callback is not called).

A published message is printed by both sides as the wrapper puts it on
the wire: each bounded sequence or string as its length ``min(len, N)``
and its first ``min(len, N)`` elements (the wrapper's ``from_c``; its
``truncated`` flag and the elements past that length are not sent).
That is the same view of the glue's message whether the environment
model's publication event carries the message as stored or converted by
``Environment.clamp`` (which keeps that length and those elements).

Both must print the same text, byte for byte: every controller input
handed to the step function, every leaf of every published message
(floats as IEEE bit patterns, NaN payloads included), the cycle marks.

A schedule (:class:`Schedule`) gives, for each cycle, the messages that
arrive before the cycle's ``ros_spinOnce`` (topic, receipt time and
leaves, in arrival order: also topics nobody subscribes to, and bursts
longer than queues), the ROS time of the cycle (what ``ros_now`` answers
once the spin returned: ``ctx_time (S k)``), and the controller's outputs
for the cycle (a table: the controller does no arithmetic, so any
difference is the glue's or the semantics').  The time before the first
spin (``ctx_time 0``, read by ``ros_init``) is the schedule's own.  Times
are nanoseconds in ``[0, 2^64)``, in any order: a clock may go back.
"""

from __future__ import annotations

import shutil
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

from pyrosgen.render import render, source_label

from pyrosgen.proof.coqdriver import CoqDriver, CoqError
from pyrosgen.proof.sexp import parse_sexp, program_items

__all__ = [
    "Leaf",
    "Struct",
    "NodeDump",
    "Message",
    "Schedule",
    "harness_source",
    "build_c_harness",
    "build_coq_runner",
    "run_side",
    "GCC_STRICT",
    "SANITIZE",
    "DifftestError",
    "leaf_token",
    "MAX_TIME",
    "CLAMPS",
    "Bounded",
]

#: The warnings the glue and the harness are compiled with.
GCC_STRICT = ("-std=c11", "-Wall", "-Wextra", "-Werror", "-pedantic")
#: Sanitizers for the sanitized build of the C side.
SANITIZE = ("-fsanitize=address,undefined", "-fno-sanitize-recover=all", "-fno-omit-frame-pointer", "-g")

HARNESS_TEMPLATE = "pyrosgen/templates/difftest_ros.c.j2"
RUNNER_TEMPLATE = "pyrosgen/templates/difftest_runner.ml.j2"
EXTRACT_TEMPLATE = "coq/templates/difftest.v.j2"


class DifftestError(CoqError):
    """Building or running a side of the differential test failed."""


# ---------------------------------------------------------------------------
# What the harness needs from the dump

@dataclass(frozen=True)
class Leaf:
    """A scalar leaf of a struct: C access path (``header.stamp.sec``,
    ``covariance[3]``), kind (``signed``, ``unsigned``, ``f32``, ``f64``),
    C type, bit width and the bounds of its values (C literals)."""

    path: str
    kind: str
    ctype: str
    bits: int
    min: str = "0"
    max: str = "0"


@dataclass(frozen=True)
class Bounded:
    """A bounded sequence or string inside a struct of the dump (rules
    4.14, 4.15): its C access path from the struct (``ranges``,
    ``header.frame_id``), its struct's name, its capacity, and the index
    of its ``len`` leaf among the struct's leaves (``truncated`` is the
    next one, then the ``data`` elements)."""

    path: str
    struct: str
    capacity: int
    first_leaf: int
    #: the leaves of one element: 1 for a scalar, all of an element
    #: struct's for a sequence of strings or messages (rule 4.15)
    elem_leaves: int = 1
    #: the element struct of a sequence of strings or messages, else None
    elem_struct: str | None = None

    @property
    def reject(self) -> bool:
        """Whether it has policy reject (``ros_rseq_...``, ``ros_rstring...``:
        ``Environment.reject_name``): a message holding it longer than its
        capacity is not delivered (``Environment.accepted``)."""
        return self.struct.startswith(("ros_rseq_", "ros_rstring"))


@dataclass(frozen=True)
class Struct:
    """A struct the harness decodes from the schedule (``fill``) and/or
    prints (``show``); ``bounded``: the bounded sequences and strings
    inside it, which the harness converts after decoding (Environment.clamp)."""

    name: str
    leaves: tuple[Leaf, ...]
    fill: bool
    show: bool
    bounded: tuple[Bounded, ...] = ()
    #: how the harness prints each leaf of a shown struct: ``(leaf, mode,
    #: conditions, bounded path, N)``, mode ``leaf`` (as it is), ``len`` (a
    #: bounded struct's length, printed as min(len, N)) or ``skip`` (its
    #: truncated flag), printed only when every condition holds (each
    #: element it is inside of is below its array's length): a published
    #: message as the wrapper puts it on the wire
    prints: tuple = ()


#: The C clamps the harness can apply to a received bounded sequence or
#: string: ``truncate`` is the wrapper's conversion (and the environment
#: model's ``Environment.clamp``); ``no_zero_fill`` is a mutant that leaves
#: the elements past the new length as they came (the differential tests
#: must catch it); ``no_reject`` is a mutant that delivers a message of
#: policy reject longer than its maximum (truncated) instead of dropping it.
CLAMPS = ("truncate", "no_zero_fill", "no_reject")

_BOUNDED_PREFIXES = ("ros_seq_", "ros_string", "ros_rseq_", "ros_rstring")


_CTYPES = {("I8", "signed"): "signed char", ("I8", "unsigned"): "unsigned char",
           ("I16", "signed"): "short", ("I16", "unsigned"): "unsigned short",
           ("I32", "signed"): "int", ("I32", "unsigned"): "unsigned int"}
_BITS = {"I8": 8, "I16": 16, "I32": 32}


def _scalar(t) -> tuple[str, str, int]:
    """(kind, C type, bits) of a scalar type of the dump."""
    if t[0] == "int":
        return (t[2], _CTYPES[(t[1], t[2])], _BITS[t[1]])
    if t[0] == "long":
        return (t[1], "long long" if t[1] == "signed" else "unsigned long long", 64)
    if t == ["float", "F64"]:
        return ("f64", "double", 64)
    if t == ["float", "F32"]:
        return ("f32", "float", 32)
    raise DifftestError(f"the differential tests do not handle leaves of type {t}")


@dataclass
class NodeDump:
    """The parts of a node's AST dump that the harness and the schedules need."""

    items: dict
    subs: list[tuple[str, str, str, int]] = field(default_factory=list)   # fn, topic, struct, queue
    advs: list[tuple[str, str]] = field(default_factory=list)             # fn, topic
    pubs: list[tuple[str, str, str]] = field(default_factory=list)        # fn, topic, struct
    fns: dict[str, str] = field(default_factory=dict)
    u: tuple[str, str] = ("", "")
    y: tuple[str, str] = ("", "")

    @classmethod
    def from_text(cls, sexp_text: str) -> "NodeDump":
        d = cls(program_items(parse_sexp(sexp_text)))
        for name, (ef, _params, _res) in d.items["externals"].items():
            tag = ef[0]
            if tag == "ros_subscribe":
                d.subs.append((name, str(ef[1]), ef[2], int(ef[3])))
            elif tag == "ros_advertise":
                d.advs.append((name, str(ef[1])))
            elif tag == "ros_publish":
                d.pubs.append((name, str(ef[1]), ef[2]))
            elif tag in ("controller_initialize", "controller_step"):
                d.fns["init" if tag == "controller_initialize" else "step"] = name
                d.u = (ef[1], d.items["gvars"][ef[1]][1])
                d.y = (ef[2], d.items["gvars"][ef[2]][1])
            else:
                d.fns[tag] = name
        missing = {"ros_init", "ros_ok", "ros_spinOnce", "ros_rate_sleep", "init", "step"} - set(d.fns)
        if missing:
            raise DifftestError(f"the program lacks the external functions {sorted(missing)}")
        return d

    def leaves(self, struct: str) -> tuple[Leaf, ...]:
        """Every scalar leaf of ``struct``, in member order, arrays expanded."""
        out: list[Leaf] = []

        def go(t, path: str) -> None:
            if t[0] == "struct":
                for m, mt in self.items["structs"][t[1]]:
                    go(mt, f"{path}.{m}" if path else m)
            elif t[0] == "array":
                for k in range(int(t[2])):
                    go(t[1], f"{path}[{k}]")
            else:
                kind, ctype, bits = _scalar(t)
                if kind == "signed":
                    lo, hi = f"(-{2 ** (bits - 1) - 1}LL - 1)", f"{2 ** (bits - 1) - 1}LL"
                elif kind == "unsigned":
                    lo, hi = "0", f"{2 ** bits - 1}ULL"
                else:
                    lo, hi = "0", "0"
                out.append(Leaf(path, kind, ctype, bits, lo, hi))

        go(["struct", struct], "")
        return tuple(out)

    def bounded_shape(self, name: str) -> tuple[int, list] | None:
        """The capacity and element type of struct ``name`` if it is a
        bounded sequence or string as the environment model recognises one
        (``Environment.bounded_name``, ``clamp_seq``: the name's prefix and
        the members ``len`` (unsigned int), ``truncated`` (unsigned char),
        ``data`` (an array of scalars or, a sequence of strings or messages,
        rule 4.15, of structs)), else ``None``."""
        members = self.items["structs"].get(name)
        if not name.startswith(_BOUNDED_PREFIXES) or members is None or len(members) != 3:
            return None
        (l, lt), (t, tt), (dname, dt) = members
        if (l, t, dname) != ("len", "truncated", "data") or lt != ["int", "I32", "unsigned"] \
                or tt != ["int", "I8", "unsigned"] or dt[0] != "array" or dt[1][0] == "array":
            return None
        return int(dt[2]), dt[1]

    def bounded_capacity(self, name: str) -> int | None:
        """The capacity of struct ``name`` if it is a bounded sequence or
        string (:meth:`bounded_shape`), else ``None``."""
        shape = self.bounded_shape(name)
        return shape[0] if shape is not None else None

    def leaf_count(self, t) -> int:
        """The number of scalar leaves of a type of the dump."""
        if t[0] == "struct":
            return sum(self.leaf_count(mt) for _, mt in self.items["structs"][t[1]])
        if t[0] == "array":
            return int(t[2]) * self.leaf_count(t[1])
        return 1

    def clamped(self, roots) -> list[tuple[str, int, str | None, tuple[tuple[str, str], ...]]]:
        """The bounded structs that the harness converts in messages of the
        structs ``roots``, inner ones first (through the elements of
        sequences of strings or messages, rule 4.15): ``(struct, capacity,
        element struct or None, bounded structs inside one element as
        (C access suffix, struct))``."""
        out: dict[str, tuple] = {}

        def add(name: str) -> None:
            if name in out:
                return
            n, et = self.bounded_shape(name)
            inner: tuple[tuple[str, str], ...] = ()
            elem = et[1] if et[0] == "struct" else None
            if elem is not None:
                if self.bounded_shape(elem) is not None:
                    inner = (("", elem),)
                else:
                    inner = tuple((f".{b.path}", b.struct) for b in self.bounded(elem))
                for _, st in inner:
                    add(st)
            out[name] = (name, n, elem, inner)

        for r in roots:
            for b in self.bounded(r):
                add(b.struct)
        return list(out.values())

    def bounded(self, struct: str) -> tuple[Bounded, ...]:
        """The bounded sequences and strings inside ``struct`` (through
        nested structs and arrays), in member order."""
        out: list[Bounded] = []
        count = 0

        def go(t, path: str) -> None:
            nonlocal count
            if t[0] == "struct":
                shape = self.bounded_shape(t[1])
                if shape is not None and path:
                    n, et = shape
                    k = self.leaf_count(et)
                    out.append(Bounded(path, t[1], n, count, k, et[1] if et[0] == "struct" else None))
                    count += 2 + n * k
                    return
                for m, mt in self.items["structs"][t[1]]:
                    go(mt, f"{path}.{m}" if path else m)
            elif t[0] == "array":
                for k in range(int(t[2])):
                    go(t[1], f"{path}[{k}]")
            else:
                count += 1

        go(["struct", struct], "")
        return tuple(out)

    def root_structs(self) -> list[str]:
        """The structs the harness reads or prints: messages, inputs, outputs."""
        out: list[str] = []
        for s in [st for _, _, st, _ in self.subs] + [st for _, _, st in self.pubs] + [self.u[1], self.y[1]]:
            if s not in out:
                out.append(s)
        return out


def _prints(d: "NodeDump", leaves: tuple[Leaf, ...], bounded: tuple[Bounded, ...]) -> tuple:
    """How the harness prints ``leaves`` of a struct whose bounded
    sequences and strings ``bounded`` go on the wire as their first
    min(len, N) elements (a published message; :attr:`Struct.prints`):
    ``(leaf, mode, conditions, bounded path, capacity)``, the conditions
    (C expressions on ``p``) under which it is on the wire: the elements
    it is inside of are below their arrays' lengths.  Inside an element of
    a sequence of strings or messages (rule 4.15), the element's own
    strings and sequences go on the wire the same way, in turn."""
    role: dict[int, tuple] = {}

    def mark(path: str, first: int, cap: int, k: int, elem: str | None, conds: tuple[str, ...]) -> None:
        role[first] = ("len", conds, path, cap)
        role[first + 1] = ("skip", conds, path, cap)
        for j in range(cap):
            c = (*conds, f"{j}u < p->{path}.len")
            base = first + 2 + j * k
            for t in range(k):
                role[base + t] = ("leaf", c, path, cap)
            if elem is None:
                continue
            epath = f"{path}.data[{j}]"
            shape = d.bounded_shape(elem)
            if shape is not None:
                n2, et2 = shape
                mark(epath, base, n2, d.leaf_count(et2), et2[1] if et2[0] == "struct" else None, c)
            else:
                for ib in d.bounded(elem):
                    mark(f"{epath}.{ib.path}", base + ib.first_leaf, ib.capacity, ib.elem_leaves,
                         ib.elem_struct, c)

    for b in bounded:
        mark(b.path, b.first_leaf, b.capacity, b.elem_leaves, b.elem_struct, ())
    return tuple((leaf, *role.get(i, ("leaf", (), "", 0))) for i, leaf in enumerate(leaves))


def harness_source(sexp_text: str, header_name: str, source: str = "the AST dump",
                   clamp: str = "truncate") -> str:
    """The C source of the fake ROS C API and the test controller
    (``clamp``: one of :data:`CLAMPS`, the conversion of a received
    bounded sequence or string)."""
    if clamp not in CLAMPS:
        raise ValueError(f"unknown clamp {clamp!r}; expected one of {CLAMPS}")
    d = NodeDump.from_text(sexp_text)
    filled = {st for _, _, st, _ in d.subs} | {d.y[1]}
    shown = {st for _, _, st in d.pubs} | {d.u[1], d.y[1]}
    published = {st for _, _, st in d.pubs}
    structs = [Struct(s, d.leaves(s), s in filled, s in shown, d.bounded(s) if s in filled else (),
                      _prints(d, d.leaves(s), d.bounded(s) if s in published else ()))
               for s in d.root_structs()]
    kinds = sorted({leaf.kind for s in structs if s.fill for leaf in s.leaves})
    clamped = d.clamped([s.name for s in structs if s.bounded])
    return render("difftest_ros.c.j2",
        template=HARNESS_TEMPLATE, source=source_label(source), header=header_name, structs=structs, kinds=kinds,
        fns=d.fns, subs=d.subs, advs=d.advs, pubs=d.pubs, u=d.u, y=d.y, clamped=clamped, clamp=clamp)


# ---------------------------------------------------------------------------
# Building the two sides

def run_tool(argv: list[str], cwd: Path, what: str, timeout: float = 900) -> subprocess.CompletedProcess:
    """Run a compiler or harness of a differential test; a failure raises
    :class:`DifftestError` with the end of its output."""
    proc = subprocess.run(argv, cwd=str(cwd), capture_output=True, text=True, errors="replace",
                          check=False, timeout=timeout)
    if proc.returncode != 0:
        raise DifftestError(f"{what} failed (exit status {proc.returncode})",
                            (proc.stdout + proc.stderr).splitlines()[-30:])
    return proc


def build_c_harness(out_dir: str | Path, node: str, work: str | Path, *, sanitize: bool = False,
                    opt: str = "-O1", name: str | None = None, clamp: str = "truncate") -> Path:
    """Compile the printed glue of ``out_dir`` (``pyrosgen generate`` output)
    with the harness, with :data:`GCC_STRICT` warnings (and the sanitizers
    of :data:`SANITIZE` if ``sanitize``; ``clamp``: the harness's
    conversion of received bounded sequences, :data:`CLAMPS`).  Returns
    the executable."""
    out_dir, work = Path(out_dir).resolve(), Path(work)
    work.mkdir(parents=True, exist_ok=True)
    glue, header, sexp = out_dir / f"{node}_glue.c", out_dir / f"{node}_types.h", out_dir / f"{node}.sexp"
    src = work / f"{name or node}_difftest_ros.c"
    src.write_text(harness_source(sexp.read_text(), header.name, sexp.name, clamp=clamp), encoding="ascii")
    exe = work / (name or f"{node}_c{'_san' if sanitize else ''}")
    argv = ["gcc", *GCC_STRICT, opt, *(SANITIZE if sanitize else ()), "-I", str(out_dir),
            str(glue), str(src), "-o", str(exe)]
    run_tool(argv, work, "gcc (differential-test harness)")
    return exe


def build_coq_runner(out_dir: str | Path, node: str, work: str | Path,
                     driver: CoqDriver | None = None) -> Path:
    """Compile the per-node Coq file of ``out_dir``, extract
    ``Interp.run_program`` and its ``the_program`` to OCaml, and compile the
    runner.  Returns the executable."""
    drv = driver or CoqDriver()
    out_dir, work = Path(out_dir).resolve(), Path(work).resolve()
    coq = work / "coq"
    coq.mkdir(parents=True, exist_ok=True)
    vfile = coq / f"{node}.v"
    shutil.copyfile(out_dir / f"{node}.v", vfile)
    lib = (coq, "RosgenNode")
    drv.coqc(vfile, lib)
    module = f"RosgenNode.{node}"
    (coq / "Extract.v").write_text(render("difftest.v.j2",
        template=EXTRACT_TEMPLATE, module=module, output="difftest.ml"), encoding="ascii")
    res = drv.run([drv.tool("coqc"), "-q", *drv.load_path([lib]), "Extract.v"], coq)
    if not res.ok:
        raise DifftestError("extraction of the interpreter failed", res.output.splitlines()[-20:])
    (coq / "runner.ml").write_text(render("difftest_runner.ml.j2",
        template=RUNNER_TEMPLATE, module="Difftest"), encoding="ascii")
    exe = work / f"{node}_coq"
    res = drv.run([*drv.ocamlopt(), "-w", "-a", "difftest.mli", "difftest.ml", "runner.ml",
                   "-o", str(exe)], coq)
    if not res.ok:
        raise DifftestError("ocamlopt failed on the extracted interpreter", res.output.splitlines()[-20:])
    return exe


def run_side(exe: str | Path, schedule_text: str, timeout: float = 120) -> str:
    """Run one side on a schedule; its trace (stdout).  A non-zero exit
    (harness error, sanitizer report, interpreter stuck) raises."""
    proc = subprocess.run([str(exe)], input=schedule_text, capture_output=True, text=True,
                          check=False, timeout=timeout)
    if proc.returncode != 0:
        raise DifftestError(f"{Path(exe).name} failed (exit status {proc.returncode})",
                            proc.stderr.splitlines()[-30:])
    return proc.stdout


# ---------------------------------------------------------------------------
# Schedules

#: Times are ROS times in nanoseconds, as ``ros_now`` returns them.
MAX_TIME = (1 << 64) - 1


@dataclass(frozen=True)
class Message:
    """A message arriving on ``topic``: its leaves as schedule tokens
    (integers in decimal, floats as ``0x`` bit patterns) and its receipt
    time (``Environment.ar_time``, what ``ros_now`` answers in its
    callback)."""

    topic: str
    leaves: tuple[str, ...]
    time: int = 0


@dataclass(frozen=True)
class Schedule:
    """Per cycle: the messages arriving before its spin, in order, and the
    controller's outputs (leaf tokens); ``times``: the time of each cycle,
    read when its spin returned (all 0 when empty); ``t0``: the time
    before the first spin."""

    cycles: tuple[tuple[tuple[Message, ...], tuple[str, ...]], ...]
    times: tuple[int, ...] = ()
    t0: int = 0

    def cycle_time(self, k: int) -> int:
        """The time of cycle ``k``: ``ctx_time (S k)``."""
        return self.times[k] if self.times else 0

    def text(self) -> str:
        if self.times and len(self.times) != len(self.cycles):
            raise ValueError("a schedule needs one time per cycle")
        for t in (self.t0, *self.times, *(m.time for msgs, _ in self.cycles for m in msgs)):
            if not 0 <= t <= MAX_TIME:
                raise ValueError(f"time {t} out of [0, 2^64)")
        lines = [f"schedule {len(self.cycles)} {self.t0}"]
        for k, (msgs, y) in enumerate(self.cycles):
            lines.append(f"cycle {k} {len(msgs)} {self.cycle_time(k)}")
            lines += [f"msg {m.topic} {m.time} {len(m.leaves)} {' '.join(m.leaves)}".rstrip() for m in msgs]
            lines.append(f"y {len(y)} {' '.join(y)}".rstrip())
        return "\n".join(lines) + "\n"


def leaf_token(leaf: Leaf, value: int) -> str:
    """The schedule token of ``value`` for ``leaf``: a float's value is its
    bit pattern (an int)."""
    if leaf.kind in ("f32", "f64"):
        return f"0x{value:0{leaf.bits // 4}x}"
    return str(value)
