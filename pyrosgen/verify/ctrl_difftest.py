"""Differential testing of diagram controllers: Coq's semantics, the
printed C under gcc, and the reference interpreter, on the same inputs.

A controller written as a block diagram (DESIGN.md rule 4.11) has three
executable descriptions, and this module runs them side by side on the
same input sequence, one step per line:

- **coq**: ``Diagram.dg_step`` folded from ``Diagram.dg_init`` over the
  inputs, applied to the node's ``Ctrl.the_diagram``, extracted to OCaml
  (``coq/templates/ctrl_difftest.v.j2``; ``ExtrOcamlBasic`` and
  ``ExtrOcamlNativeString`` only: integers stay Coq's inductive ``Z``,
  floats Flocq's ``binary_float``) and driven by
  ``pyrosgen/templates/ctrl_difftest_runner.ml.j2``.  This is the
  reference: it is what the controller theorems say ``Controller_step``
  computes (``Main.controller_step_correct``).
- **gcc -O2**: the controller C that Coq printed (``<node>_controller.c``)
  compiled on its own with ``gcc -std=c11 -pedantic-errors -O2
  -ffp-contract=off -fno-fast-math`` (ISO C: no contraction of ``a*b+c``
  into a fused multiply-add, no value-changing float optimisation) and
  linked with the driver of ``pyrosgen/templates/ctrl_difftest.c.j2``
  (strict warnings), which declares the controller's structs member for
  member and its globals ``extern``.
- **gcc -O0 asan/ubsan**: the same at ``-O0`` under
  ``-fsanitize=address,undefined -fno-sanitize-recover=all``: any
  undefined behaviour the sanitizers see (a signed overflow the printed C
  should have avoided, an out-of-bounds access) stops the run, which is a
  failure.
- **blocksim**: :mod:`pyrosgen.frontend.blocksim`, the Python reference
  interpreter of ``dg_step``.

Each side prints a header ``columns out:F ... state:S ...`` (the C side's
comes from the model, the Coq side's from the extracted diagram: they must
agree) and, per step, the output fields and the state after the step:
integers and ``bool`` in decimal, floats as their IEEE bit pattern in
hexadecimal.  :func:`compare` requires every side to print what the Coq
side prints, character for character, **except** where both values are
NaNs: then sign and payload may differ (DESIGN.md section 6.2).  C11 leaves
the sign and payload of a NaN result unspecified; the semantics
(``FloatOps``) fixes x86-64's rule, the first NaN operand made quiet, else
the default NaN ``0xFFF8...``, but gcc may exchange the operands of the
commutative ``+`` and ``*`` (it does: on ``ctrl_all_blocks.yaml``, where
two NaNs meet in a ``Sum`` or in an integrator's ``x + kt * u``, the
compiled code returns the other operand's NaN at some steps, e.g. a
negated input's sign-flipped NaN against another input's NaN).  Blocksim implements ``FloatOps``' rule and agrees with Coq
on payloads too.  No block makes a NaN's sign or payload observable
otherwise (comparisons are unordered on every NaN, a NaN is "true"
whatever its bits), so a NaN-only difference cannot hide another one;
such differences are counted in the report (``nan_payloads``).

Why the Coq side ``Require``s the compiled per-node module instead of
emitting ``the_diagram`` again from the model
(:func:`pyrosgen.proof.coqdiagram.emit_diagram`): the per-node file is what
``pyrosgen generate`` proved things about and printed the controller C from
(``Ctrl.controller_c`` is ``print_program (dg_program the_diagram)`` in the
same file), so the test compares the C with the semantics of the very term
its theorems are about, even if the emitter or the template changed since
the folder was generated.  It costs one ``coqc`` of the per-node file
(about 2 s for LandShark).

Inputs (:func:`make_steps`): per step, a value per controller input field
(a ``dict`` field -> ``int`` in blocksim's representation: signed integers
signed, floats as bit patterns), first an *edge sweep* in which each pair
of neighbouring fields of one type goes through every pair of edge values
of the type (so that ``+0.0`` meets ``-0.0`` and a NaN meets an infinity
in one block), then random values: an edge value, a small number or any
bit pattern, each a third of the time.  Seeded and reproducible.

:func:`run_ctrl_difftest` does everything; :class:`CtrlDifftest` builds
the sides once and runs them on several input sequences or on a mutated
controller C.
"""

from __future__ import annotations

import os
import random
import shutil
import struct
import subprocess
import time
from dataclasses import dataclass, field
from pathlib import Path

from pyrosgen.frontend import blocksim
from pyrosgen.frontend.model import NodeModel
from pyrosgen.frontend.msgmodel import C_TYPES
from pyrosgen.proof.coqdriver import CoqDriver
from pyrosgen.render import render, source_label
from pyrosgen.verify.difftest import GCC_STRICT, DifftestError, run_tool

__all__ = [
    "C_ISO", "O2", "SANITIZED", "SIDES", "COQ", "GCC_O2", "GCC_SAN", "BLOCKSIM", "Column", "Difference", "CtrlDifftestReport", "CtrlDifftest",
    "columns", "edge_values", "make_steps", "input_line", "harness_source", "compare", "run_ctrl_difftest",
    "is_nan_token", "token",
]

#: ISO C: the controller is compiled with these, and no warning options
#: (a diagram may have unused signals; their temporaries are set and not
#: read, which -Wall reports).
C_ISO = ("-std=c11", "-pedantic-errors")
#: The optimised build: no contraction into FMAs, no fast math.
O2 = ("-O2", "-ffp-contract=off", "-fno-fast-math")
#: The sanitized build.
SANITIZED = ("-O0", "-ffp-contract=off", "-fno-fast-math", "-fsanitize=address,undefined",
             "-fno-sanitize-recover=all", "-fno-omit-frame-pointer", "-g")

#: The sides, in the order of the report; the first is the reference.
COQ, GCC_O2, GCC_SAN, BLOCKSIM = "coq", "gcc -O2", "gcc -O0 asan/ubsan", "blocksim"
SIDES = (COQ, GCC_O2, GCC_SAN, BLOCKSIM)

HARNESS_TEMPLATE = "pyrosgen/templates/ctrl_difftest.c.j2"
RUNNER_TEMPLATE = "pyrosgen/templates/ctrl_difftest_runner.ml.j2"
EXTRACT_TEMPLATE = "coq/templates/ctrl_difftest.v.j2"

_BITS = {"bool": 8, "int32": 32, "uint32": 32, "float32": 32, "int64": 64, "uint64": 64, "float64": 64}


# ---------------------------------------------------------------------------
# Columns and tokens


@dataclass(frozen=True)
class Column:
    """A printed column: an output field (``kind`` ``out``) or a state
    member (``state``), with its signal type."""

    kind: str
    name: str
    prim: str

    @property
    def label(self) -> str:
        return f"{self.kind}:{self.name}"


def _diagram(model: NodeModel):
    d = model.controller.diagram
    if d is None:
        raise DifftestError(f"node {model.name}: the controller is not a block diagram")
    return d


def columns(model: NodeModel) -> list[Column]:
    """The printed columns: the output fields in C order, then the state
    members (UnitDelays and DiscreteIntegrators in the model's order)."""
    d = _diagram(model)
    return ([Column("out", f.name, f.prim) for f in model.controller.outputs.fields]
            + [Column("state", b.name, b.prim) for b in d.states])


def _header(model: NodeModel) -> str:
    return " ".join(["columns", *(c.label for c in columns(model))])


def _pattern(prim: str, v: int) -> int:
    """The bit pattern of a value in blocksim's representation."""
    bits = _BITS[prim]
    if prim in ("int32", "int64"):
        return v % (1 << bits)
    if prim == "bool":
        if not 0 <= v <= 255:
            raise ValueError(f"a bool input is a byte, not {v}")
        return v
    if not 0 <= v < 1 << bits:
        raise ValueError(f"{v} is not a value of {prim}")
    return v


def token(prim: str, v: int) -> str:
    """A printed value: floats as their bit pattern, integers in decimal."""
    if prim == "float64":
        return f"0x{v:016x}"
    if prim == "float32":
        return f"0x{v:08x}"
    return str(v)


def input_line(model: NodeModel, step: dict[str, int]) -> str:
    """The input line of one step: each input field's bit pattern."""
    out = []
    for f in model.controller.inputs.fields:
        if f.name not in step:
            raise KeyError(f"the step has no value for input {f.name}")
        out.append(f"0x{_pattern(f.prim, step[f.name]):0{_BITS[f.prim] // 4}x}")
    return " ".join(out)


def is_nan_token(prim: str, text: str) -> bool:
    """Whether a printed float value is a NaN."""
    if prim not in ("float32", "float64") or not text.startswith("0x"):
        return False
    b = int(text, 16)
    if prim == "float64":
        return (b >> 52) & 0x7FF == 0x7FF and b & ((1 << 52) - 1) != 0
    return (b >> 23) & 0xFF == 0xFF and b & ((1 << 23) - 1) != 0


# ---------------------------------------------------------------------------
# Inputs

_F64_EDGES = (
    0x0000000000000000, 0x8000000000000000,          # +0, -0
    0x7FF0000000000000, 0xFFF0000000000000,          # +inf, -inf
    0x7FF8000000000000, 0xFFF800000000ABCD,          # quiet NaNs (the second negative, with a payload)
    0x7FF0000000000123,                              # a signalling NaN with a payload
    0x0000000000000001, 0x000FFFFFFFFFFFFF,          # the smallest and the largest subnormal
    0x0010000000000000,                              # the smallest normal
    0x7FEFFFFFFFFFFFFF, 0xFFEFFFFFFFFFFFFF,          # DBL_MAX, -DBL_MAX
    0x3FF0000000000000, 0xBFF0000000000000,          # 1.0, -1.0
)
_F32_EDGES = (
    0x00000000, 0x80000000, 0x7F800000, 0xFF800000, 0x7FC00000, 0xFFC0ABCD, 0x7F800123,
    0x00000001, 0x007FFFFF, 0x00800000, 0x7F7FFFFF, 0xFF7FFFFF, 0x3F800000, 0xBF800000,
)
_INT_EDGES = {
    "int32": (-(1 << 31), -(1 << 31) + 1, -1, 0, 1, (1 << 31) - 2, (1 << 31) - 1),
    "uint32": (0, 1, (1 << 31) - 1, 1 << 31, (1 << 32) - 2, (1 << 32) - 1),
    "int64": (-(1 << 63), -(1 << 63) + 1, -(1 << 31), -1, 0, 1, (1 << 32), (1 << 63) - 2, (1 << 63) - 1),
    "uint64": (0, 1, (1 << 32) - 1, (1 << 63) - 1, 1 << 63, (1 << 64) - 2, (1 << 64) - 1),
    "bool": (0, 1, 2, 255),
}


def edge_values(prim: str) -> tuple[int, ...]:
    """The edge values of a signal type (blocksim's representation):
    ±0, ±inf, quiet NaNs (one negative with a payload), a signalling NaN
    with a payload, the smallest and largest subnormals, the smallest
    normal, ±the largest finite value, ±1 for floats; the extremes, their
    neighbours, -1, 0 and 1 for integers; 0, 1, 2 and 255 for ``bool``
    (a ``bool`` field is an ``unsigned char``: any non-zero byte is true)."""
    if prim == "float64":
        return _F64_EDGES
    if prim == "float32":
        return _F32_EDGES
    return _INT_EDGES[prim]


def _random_value(prim: str, rng: random.Random) -> int:
    k = rng.random()
    if k < 1 / 3:
        return rng.choice(edge_values(prim))
    if prim == "float64":
        if k < 2 / 3:
            return struct.unpack("<Q", struct.pack("<d", rng.uniform(-3.0, 3.0)))[0]
        return rng.getrandbits(64)
    if prim == "float32":
        if k < 2 / 3:
            return struct.unpack("<I", struct.pack("<f", rng.uniform(-3.0, 3.0)))[0]
        return rng.getrandbits(32)
    if prim == "bool":
        return rng.choice((0, 1)) if k < 2 / 3 else rng.randrange(256)
    bits = _BITS[prim]
    signed = prim in ("int32", "int64")
    if k < 2 / 3:
        return rng.randint(-100, 100) if signed else rng.randint(0, 200)
    n = rng.getrandbits(bits)
    return n - (1 << bits) if signed and n >= 1 << (bits - 1) else n


def make_steps(model: NodeModel, n: int, seed: int = 0, *, edges: bool = True) -> list[dict[str, int]]:
    """``n`` steps of inputs: the edge sweep first (if ``edges``; cut
    short if ``n`` is smaller), then random values, from ``seed``.

    The sweep takes ``E * E`` steps for the type with the most edge
    values ``E``: the fields of each type, in C order, get, at sweep step
    ``k``, edge ``k mod E`` (the 1st, 3rd, ... field of the type) or edge
    ``(k div E) mod E`` (the 2nd, 4th, ...), so any two neighbouring fields
    of one type meet in every pair of edge values."""
    rng = random.Random(seed)
    fields = model.controller.inputs.fields
    by_type: dict[str, list[str]] = {}
    for f in fields:
        if f.prim not in _BITS:
            raise DifftestError(f"input {f.name} has type {f.prim}, not a signal type")
        by_type.setdefault(f.prim, []).append(f.name)
    sweep = max((len(edge_values(q)) ** 2 for q in by_type), default=0) if edges else 0
    steps: list[dict[str, int]] = []
    for k in range(min(n, sweep)):
        step = {}
        for q, names in by_type.items():
            ev = edge_values(q)
            e = len(ev)
            for j, name in enumerate(names):
                step[name] = ev[k % e] if j % 2 == 0 else ev[(k // e) % e]
        steps.append({f.name: step[f.name] for f in fields})
    while len(steps) < n:
        steps.append({f.name: _random_value(f.prim, rng) for f in fields})
    return steps


# ---------------------------------------------------------------------------
# The report


@dataclass(frozen=True)
class Difference:
    """A step and column where a side printed something else than the Coq
    side: each side's value (``None``: the side printed no such step)."""

    step: int
    column: str
    values: dict[str, str | None]

    def __str__(self) -> str:
        vals = ", ".join(f"{side} {v if v is not None else '(nothing)'}" for side, v in self.values.items())
        return f"step {self.step}, {self.column}: {vals}"


@dataclass
class CtrlDifftestReport:
    """The result of a comparison.  ``first`` is the first difference
    (lowest step, then column order), ``None`` if every side agrees with
    the Coq side; ``differences`` counts the (step, column) pairs that
    differ, ``nan_payloads`` those where only a NaN's sign or payload
    differs (allowed)."""

    node: str
    steps: int
    sides: tuple[str, ...]
    columns: tuple[str, ...]
    first: Difference | None
    differences: int
    nan_payloads: int
    outputs: dict[str, list[str]] = field(repr=False, default_factory=dict)
    seconds: dict[str, float] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return self.first is None

    def summary(self) -> str:
        head = (f"{self.node}: {self.steps} steps, {len(self.columns)} columns, sides "
                f"{', '.join(self.sides)}: ")
        if self.ok:
            return head + f"all agree ({self.nan_payloads} NaN sign/payload differences allowed)"
        return head + f"{self.differences} differences; first: {self.first}"


def compare(model: NodeModel, outputs: dict[str, list[str]], steps: int | None = None) -> CtrlDifftestReport:
    """Compare the sides' printed lines (without their header) with the
    first side's (the reference: Coq).  A value differs unless it is the
    reference's text, or both are NaNs of the column's float type."""
    cols = columns(model)
    sides = tuple(outputs)
    ref = sides[0]
    n = steps if steps is not None else max(len(v) for v in outputs.values())
    first: Difference | None = None
    diffs = nans = 0
    split = {s: [ln.split() for ln in outputs[s]] for s in sides}
    for k in range(n):
        rows = {s: (split[s][k] if k < len(split[s]) else None) for s in sides}
        for i, col in enumerate(cols):
            vals = {s: (r[i] if r is not None and i < len(r) else None) for s, r in rows.items()}
            a = vals[ref]
            bad = nan_only = False
            for s in sides[1:]:
                b = vals[s]
                if b == a and a is not None:
                    continue
                if a is not None and b is not None and is_nan_token(col.prim, a) and is_nan_token(col.prim, b):
                    nan_only = True
                    continue
                bad = True
            if bad:
                diffs += 1
                if first is None:
                    first = Difference(k, col.label, vals)
            elif nan_only:
                nans += 1
        # a row with more tokens than columns
        for s, r in rows.items():
            if r is not None and len(r) != len(cols):
                diffs += 1
                if first is None:
                    first = Difference(k, f"({len(r)} values for {len(cols)} columns)",
                                       {x: (" ".join(rows[x]) if rows[x] is not None else None) for x in sides})
    return CtrlDifftestReport(model.name, n, sides, tuple(c.label for c in cols), first, diffs, nans, outputs)


# ---------------------------------------------------------------------------
# The sides


def harness_source(model: NodeModel, source: str = "the node model") -> str:
    """The C driver of the controller (``ctrl_difftest.c.j2``)."""
    c = model.controller
    d = _diagram(model)
    states = [(b.name, b.prim) for b in d.states]
    for f in (*c.inputs.fields, *c.outputs.fields):
        if f.prim not in _BITS:
            raise DifftestError(f"field {f.name} has type {f.prim}, not a signal type")
    return render("ctrl_difftest.c.j2",
        template=HARNESS_TEMPLATE, source=source_label(source), ctrl=c.name, u=c.inputs, y=c.outputs,
        state=(c.state_var, c.state_struct) if states else None, states=states, ctypes=C_TYPES,
        line_max=21 * len(c.inputs.fields) + 64)


class CtrlDifftest:
    """The sides of the differential test of one node's diagram controller,
    built in ``work``.

    ``generated`` is the folder ``pyrosgen generate`` wrote for the model
    (``<node>_controller.c`` and ``<node>.v`` are read there); without it,
    the model is generated into ``work/generated`` first
    (:func:`pyrosgen.generate.generate_model`)."""

    def __init__(self, model: NodeModel, work: str | Path, *, generated: str | Path | None = None,
                 driver: CoqDriver | None = None):
        _diagram(model)
        self.model = model
        self.work = Path(work).resolve()
        self.work.mkdir(parents=True, exist_ok=True)
        self.driver = driver
        self.seconds: dict[str, float] = {}
        if generated is None:
            from pyrosgen.generate import generate_model

            generated = self.work / "generated"
            t = time.monotonic()
            generate_model(model, generated, driver=driver)
            self.seconds["generate"] = time.monotonic() - t
        self.generated = Path(generated).resolve()
        self.controller_c = self.generated / f"{model.name}_controller.c"
        if not self.controller_c.is_file():
            raise DifftestError(f"{self.controller_c} does not exist: not a generated diagram controller")
        self._exes: dict[str, Path] = {}

    # -- C ---------------------------------------------------------------------

    def build_c(self, controller_c: str | Path | None = None, *, sanitize: bool = False,
                name: str | None = None) -> Path:
        """Compile ``controller_c`` (default: the generated one) and the
        driver: :data:`O2`, or :data:`SANITIZED` if ``sanitize``."""
        ctrl = Path(controller_c).resolve() if controller_c is not None else self.controller_c
        name = name or ("c_san" if sanitize else "c_o2")
        out = self.work / name
        out.mkdir(parents=True, exist_ok=True)
        harness = out / "ctrl_difftest_main.c"
        harness.write_text(harness_source(self.model, self.model.source.name if self.model.source else "the model"),
                           encoding="ascii")
        flags = list(SANITIZED if sanitize else O2)
        t = time.monotonic()
        objs = []
        for src, warn in ((ctrl, C_ISO), (harness, GCC_STRICT)):
            obj = out / (src.stem + ".o")
            run_tool(["gcc", *warn, *flags, "-c", str(src), "-o", str(obj)], out, f"gcc {' '.join(flags)} on {src.name}")
            objs.append(str(obj))
        exe = out / "ctrl_difftest"
        run_tool(["gcc", *flags, *objs, "-o", str(exe)], out, "linking the C side")
        self.seconds[f"build {name}"] = time.monotonic() - t
        return exe

    # -- Coq -------------------------------------------------------------------

    def build_coq(self) -> Path:
        """Compile the per-node Coq file of the generated folder, extract
        ``dg_step``, ``dg_init`` and its ``Ctrl.the_diagram``, and compile
        the runner.  Returns the executable."""
        drv = self.driver or CoqDriver()
        node = self.model.name
        coq = self.work / "coq"
        if coq.exists():
            shutil.rmtree(coq)
        coq.mkdir(parents=True)
        t = time.monotonic()
        vfile = coq / f"{node}.v"
        shutil.copyfile(self.generated / f"{node}.v", vfile)
        lib = (coq, "RosgenNode")
        drv.coqc(vfile, lib)
        (coq / "Extract.v").write_text(render("ctrl_difftest.v.j2",
            template=EXTRACT_TEMPLATE, module=f"RosgenNode.{node}", output="ctrl_difftest.ml"), encoding="ascii")
        res = drv.run([drv.tool("coqc"), "-q", *drv.load_path([lib]), "Extract.v"], coq)
        if not res.ok:
            raise DifftestError("extraction of the diagram semantics failed", res.output.splitlines()[-20:])
        (coq / "runner.ml").write_text(render("ctrl_difftest_runner.ml.j2",
            template=RUNNER_TEMPLATE, module="Ctrl_difftest"), encoding="ascii")
        exe = self.work / "coq_side"
        res = drv.run([*drv.ocamlopt(), "-w", "-a", "ctrl_difftest.mli", "ctrl_difftest.ml", "runner.ml",
                       "-o", str(exe)], coq)
        if not res.ok:
            raise DifftestError("ocamlopt failed on the extracted semantics", res.output.splitlines()[-20:])
        self.seconds["build coq"] = time.monotonic() - t
        return exe

    def executables(self, sides: tuple[str, ...] = SIDES) -> dict[str, Path]:
        """The executables of the compiled sides among ``sides``, built on
        first use."""
        for side in sides:
            if side in self._exes or side == BLOCKSIM:
                continue
            if side == COQ:
                self._exes[side] = self.build_coq()
            elif side == GCC_O2:
                self._exes[side] = self.build_c()
            elif side == GCC_SAN:
                self._exes[side] = self.build_c(sanitize=True)
            else:
                raise ValueError(f"unknown side {side!r}")
        return {s: self._exes[s] for s in sides if s != BLOCKSIM}

    # -- running ---------------------------------------------------------------

    def run_exe(self, exe: Path, text: str, what: str, timeout: float = 600) -> list[str]:
        """Run a compiled side on the input text; its lines after the
        header, which must be the model's."""
        env = dict(os.environ, ASAN_OPTIONS="detect_leaks=0:abort_on_error=0",
                   UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1")
        proc = subprocess.run([str(exe)], input=text, capture_output=True, text=True, errors="replace",
                              check=False, timeout=timeout, env=env)
        if proc.returncode != 0 or "runtime error" in proc.stderr or "Sanitizer" in proc.stderr:
            raise DifftestError(f"the {what} side failed (exit status {proc.returncode})",
                                proc.stderr.splitlines()[-30:])
        lines = proc.stdout.splitlines()
        if not lines or lines[0] != _header(self.model):
            raise DifftestError(f"the {what} side printed the columns {lines[0] if lines else '(nothing)'!r}, "
                                f"the model has {_header(self.model)!r}")
        return lines[1:]

    def run_blocksim(self, steps: list[dict[str, int]]) -> list[str]:
        """Blocksim's lines for ``steps``."""
        d = _diagram(self.model)
        outs = self.model.controller.outputs.fields
        state = blocksim.initial_state(d)
        lines = []
        for u in steps:
            state, y = blocksim.step(d, state, u)
            lines.append(" ".join([token(f.prim, y[f.name]) for f in outs]
                                  + [token(b.prim, state[b.name]) for b in d.states]))
        return lines

    def run(self, steps: list[dict[str, int]], *, sides: tuple[str, ...] = SIDES,
            extra: dict[str, Path] | None = None) -> CtrlDifftestReport:
        """Run ``sides`` (the first is the reference) and the ``extra``
        executables (name -> a C side built by :meth:`build_c`, e.g. on a
        mutated controller) on ``steps``, and compare them."""
        text = "".join(input_line(self.model, s) + "\n" for s in steps)
        exes = self.executables(sides)
        outputs: dict[str, list[str]] = {}
        seconds: dict[str, float] = dict(self.seconds)
        for side in sides:
            t = time.monotonic()
            outputs[side] = self.run_blocksim(steps) if side == BLOCKSIM else self.run_exe(exes[side], text, side)
            seconds[f"run {side}"] = time.monotonic() - t
        for name, exe in (extra or {}).items():
            t = time.monotonic()
            outputs[name] = self.run_exe(exe, text, name)
            seconds[f"run {name}"] = time.monotonic() - t
        report = compare(self.model, outputs, len(steps))
        report.seconds = seconds
        return report


def run_ctrl_difftest(model: NodeModel, steps: list[dict[str, int]], work: str | Path, *,
                      generated: str | Path | None = None, controller_c: str | Path | None = None,
                      sides: tuple[str, ...] = SIDES, driver: CoqDriver | None = None) -> CtrlDifftestReport:
    """Run the differential test of ``model``'s diagram controller on
    ``steps`` (one ``dict`` input field -> value per step, blocksim's
    representation; :func:`make_steps` makes them) in ``work``.

    ``generated``: an existing ``pyrosgen generate`` folder of the model
    (else it is generated in ``work``).  ``controller_c``: another
    controller C to test in place of the generated one on the C sides (a
    mutant, to check that the comparison catches it); the Coq side still
    reads the generated folder's per-node file."""
    t = CtrlDifftest(model, work, generated=generated, driver=driver)
    if controller_c is not None:
        for side in sides:
            if side == GCC_O2:
                t._exes[side] = t.build_c(controller_c, name="c_o2_given")
            elif side == GCC_SAN:
                t._exes[side] = t.build_c(controller_c, sanitize=True, name="c_san_given")
    return t.run(steps, sides=sides)
