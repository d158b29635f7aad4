"""ACSL contracts of the printed glue, and the Frama-C WP run that proves them.

An independent check of the final C text against the data delivery
specifications (DESIGN.md section 7, "the final C meets DDC"): the contracts
are generated here, in Python, from the node model (:class:`NodeModel`), not
from the Coq development, and proved by Frama-C's WP plug-in on the very
files that ``pyrosgen generate`` writes (``pyrosgen generate --wp``).

For each generated function (``pyrosgen/templates/wp_contracts.c.j2``):

- callback of a subscribed topic, ``void <c>_callback(struct M *msg)``
  (Figure 10): requires ``\\valid_read(msg)`` and ``msg`` separated from every
  global (and, implied by ``\\valid_read(msg)``, the validity of each leaf
  ``&msg->f``: stated so that WP's simplifier discharges the memory-access
  goals of ``-wp-rte`` by itself instead of calling a prover); assigns
  exactly the leaves of ``<c>_msg`` that the node reads through it
  (:meth:`NodeModel.read_leaves`: those named by input relations that are
  not direct, and the ``sec``/``nsec`` of a stamp copied from the topic)
  and the fields of ``Controller_U`` of the topic's direct input
  relations (DESIGN.md rule 4.16, :meth:`NodeModel.direct_relations`:
  array elements of an untimed topic, which the callback copies from
  ``*msg`` straight into ``Controller_U``), so that every other leaf and
  field keeps its value, and ensures each of these leaves equals the same
  leaf of ``\\old(*msg)`` and each of these fields the related leaf of
  ``\\old(*msg)`` (``\\valid_read`` stated for both);
- ``void input_glue(void)`` (Figure 12): assigns exactly the fields of
  ``Controller_U`` of the input relations that are not direct
  (:attr:`NodeModel.glue_relations`; and the derived inputs and ``c_new``
  flags below); ensures each equals the related field of the related
  topic's global;
- ``void output_glue_<c>(struct M *command)``: requires ``\\valid(command)``
  and separation from every global; assigns exactly ``*command``; ensures
  every leaf named by an output relation equals the related field of
  ``Controller_Y``, the ``sec`` and ``nsec`` of a stamped topic's stamp
  (rule 4.13, below) and the leaves of its constant strings (rule 4.14:
  ``len`` and the bytes) their values, and every other leaf is zero.

Timed topics (rule 4.12).  ``ros_now`` gets the contract ``assigns
\\nothing; ensures \\result == rosgen_wp_clock;``: the time is the value of
a global the glue never writes, so that the contracts can name the time
it reads.  The callback of a timed topic ``c`` also assigns ``c_time``,
``c_new`` and ``c_rcvd`` and ensures ``c_time == \\old(rosgen_wp_clock)``
(the receipt time), ``c_new == 1`` and ``c_rcvd == 1``.  ``input_glue``
also assigns every ``c_new`` and ensures, with ``AGE(c)`` the rule's age
in ns (``\\old(rosgen_wp_clock) - \\old(c_time)`` if ``\\old(c_rcvd)`` and
the clock did not go back, 0 if it did, 2^64 - 1 if nothing arrived): an
input with a fallback equals the fallback if ``T * 10^6 < AGE(c)``, else
the message's field; ``is_new`` and ``received`` inputs equal
``\\old(c_new)`` and ``\\old(c_rcvd)``; an ``age_ms`` input equals
``AGE(c) / 10^6`` if ``AGE(c) <= 4294967295999999``, else 4294967295; and
``c_new == 0``.  A float fallback is compared with a ``static const``
global initialised with its exact (hexadecimal) C literal, which WP reads
(constant globals' initialisers).  WP's simplifier reads float constants
as real numbers, so to it a fallback ``-0.0`` is ``+0.0``: the sign of a
zero fallback is left to the differential tests, which compare bits.

Stamps (rule 4.13).  As for the clock, ``ros_time_sec`` and
``ros_time_nsec`` get the contracts ``assigns \\nothing; ensures \\result
== rosgen_wp_sec;`` and ``... == rosgen_wp_nsec;`` (two ``unsigned int``
globals the glue never writes, declared, and stated separated from every
pointer argument, only when a topic is stamped with ``stamp: now``).  The
output glue of a topic with ``stamp: now`` ensures ``header.stamp.sec ==
\\old(rosgen_wp_sec)`` and ``header.stamp.nsec == \\old(rosgen_wp_nsec)``;
of one with ``stamp: {from: s}``, ``header.stamp.sec ==
\\old(s_msg.header.stamp.sec)`` and the same for ``nsec``: the stamp of
``s``'s global, which ``s``'s callback keeps (:meth:`NodeModel.read_leaves`).
This is ``DDC.published_value``: the cycle's time, or the source
message's stamp.  On ROS 2 (``builtin_interfaces/Time``: ``int32 sec``,
``uint32 nanosec``) the seconds are ``(int)\\old(rosgen_wp_sec)``
(``DDC.stamp_sec``: ACSL's cast to ``int`` wraps modulo 2^32, as the C
conversion gcc makes) and ``nsec`` is ``nanosec``.

Equality of leaves.  ACSL's ``==`` on floating-point values compares their
*real* values (WP translates ``a == b`` to ``of_f64(a) = of_f64(b)``): it
identifies +0.0 with -0.0 and says nothing about NaN, so it is too weak for
a copy.  Floating-point leaves are therefore compared with the predicates
``rosgen_same_f64`` / ``rosgen_same_f32``: equality of two one-member
structs ``{box \\with .v = a} == {box \\with .v = b}``.  WP models struct
equality as the conjunction of the members' *logical* equality, so the
predicate is exactly ``a = b`` on WP's IEEE values (Why3's ``ieee_float``:
+0.0 and -0.0 are distinct, a NaN equals itself).  This is sound for copies
of any value including NaN, and strictly stronger than ``==`` elsewhere.
What the model cannot see is the payload of a NaN (it has one NaN): payload
preservation is checked bit for bit by the differential tests
(:mod:`pyrosgen.verify.difftest`).  Integer leaves are compared with ``==``
(mathematical integers: exact).

Memory-model hypotheses.  WP's typed model may assume that pointers are
separated from globals; it reports such assumptions as "Memory model
hypotheses".  The contracts state the separation of each pointer argument
from every global themselves, and :func:`run_wp` fails if WP reports a
hypothesis that the contract does not state, so nothing is assumed silently.

The run fails (:class:`WPError`, a :class:`~pyrosgen.proof.coqdriver.CoqError`:
exit code 2) unless every goal is proved.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import time
from dataclasses import dataclass, field
from pathlib import Path

from pyrosgen.render import render, source_label

from pyrosgen.proof.coqdriver import CoqError
from pyrosgen.frontend.model import NodeModel
from pyrosgen import procs

__all__ = [
    "run_wp_file",
    "contract_frame",
    "WPError",
    "WPResult",
    "Contract",
    "contracts",
    "render_wrapper",
    "run_wp",
    "memory_hypotheses",
    "WRAPPER_TEMPLATE",
    "PROVERS",
]

#: The wrapper template, relative to the repository root.
WRAPPER_TEMPLATE = "pyrosgen/templates/wp_contracts.c.j2"

#: Provers tried, in order, among those that Why3 detects.
PROVERS = ("alt-ergo", "z3", "cvc4", "cvc5")
_WHY3_NAMES = {"alt-ergo": "Alt-Ergo", "z3": "Z3", "cvc4": "CVC4", "cvc5": "CVC5"}


class WPError(CoqError):
    """Frama-C WP did not prove every goal, or could not run (exit 2)."""


@dataclass(frozen=True)
class Box:
    """A one-member struct through which leaves of ``c_type`` are compared."""

    c_type: str
    struct: str
    var: str
    predicate: str


_BOXES = {
    "float64": Box("double", "rosgen_wp_box_f64", "rosgen_wp_f64", "rosgen_same_f64"),
    "float32": Box("float", "rosgen_wp_box_f32", "rosgen_wp_f32", "rosgen_same_f32"),
}


@dataclass(frozen=True)
class Contract:
    """The ACSL contract of one glue function."""

    name: str
    proto: str
    requires: tuple[str, ...]
    assigns: tuple[str, ...]
    ensures: tuple[str, ...]
    pointer: str | None = None          #: the pointer argument, if any
    separated: tuple[str, ...] = ()     #: what it is stated separated from


@dataclass
class WPResult:
    """The outcome of a WP run."""

    proved: int
    total: int
    seconds: float
    provers: tuple[str, ...]
    functions: tuple[str, ...]
    wrapper: Path | None = None
    output: str = ""
    by_prover: dict[str, int] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return self.total > 0 and self.proved == self.total

    @property
    def prover(self) -> str:
        """What proved the goals, with counts: ``Qed 87`` (WP's simplifier), ``Z3 4.8.12 3``."""
        return ", ".join(f"{k} {v}" for k, v in self.by_prover.items())

    def summary(self) -> str:
        return (f"WP: {self.proved}/{self.total} goals proved ({self.prover}; {len(self.functions)} functions, "
                f"{self.seconds:.1f} s)")


def _same(prim: str, a: str, b: str) -> str:
    """The ACSL statement that leaves [a] and [b] of primitive [prim] are
    equal.  For floats, the struct equality is written out rather than
    through the predicate [rosgen_same_f64] (whose definition it is): WP's
    simplifier (Qed) does not unfold user predicates, but decides struct
    equalities of known members at once."""
    box = _BOXES.get(prim)
    if box is None:
        return f"{a} == {b}"
    return f"{{ {box.var} \\with .v = {a} }} == {{ {box.var} \\with .v = {b} }}"


def _string_leaves(t) -> dict[str, str]:
    """The value of each leaf of the constant strings of published topic
    ``t`` (rule 4.14) that is not zero: ``len`` and the bytes, by leaf path."""
    out = {}
    for s in t.strings:
        out[f"{s.path_text}.len"] = str(len(s.data))
        out.update({f"{s.path_text}.data[{i}]": str(b) for i, b in enumerate(s.data) if b})
    return out


def _zero(prim: str) -> str:
    return {"float64": "(double)0", "float32": "(float)0"}.get(prim, "0")


#: The global whose value ``ros_now`` returns in the contracts (rule 4.12).
CLOCK = "rosgen_wp_clock"
#: The globals whose values ``ros_time_sec`` and ``ros_time_nsec`` return
#: in the contracts (rule 4.13, ``stamp: now``).
STAMP_SEC = "rosgen_wp_sec"
STAMP_NSEC = "rosgen_wp_nsec"
#: The largest ``unsigned long long``: the age of a topic without message.
_NO_AGE = (1 << 64) - 1
#: The largest age in ns whose milliseconds fit in a ``uint32``.
_MAX_AGE = 4294967295999999


def _stamps_now(model: NodeModel) -> bool:
    """Whether a published topic is stamped with the cycle's time (rule
    4.13, ``stamp: now``): the glue then calls ``ros_time_sec`` and
    ``ros_time_nsec``."""
    return any(t.stamped and t.stamp_from is None for t in model.published)


def _stamp_values(model: NodeModel, t) -> dict[str, str]:
    """The value of the ``sec`` and ``nsec`` leaves of published topic
    ``t``'s stamp (rule 4.13), by leaf path, as ACSL terms over the state
    before the output glue: ``\\old(rosgen_wp_sec)`` for ``stamp: now``
    (on ROS 2, ``(int)\\old(rosgen_wp_sec)`` into the ``int32 sec``, ACSL's
    cast being modulo 2^32 as the C's is, and ``nanosec`` for ``nsec``), the
    source topic's global ``\\old(<src>_msg.header.stamp.sec)`` for a stamp
    copied from a subscribed topic (``DDC.published_value``); empty if
    ``t`` is not stamped."""
    stamp = dict(model.stamps).get(t.c_name)
    if stamp is None:
        return {}
    src = dict(model.stamp_from).get(t.c_name)
    path = ".".join(stamp)
    # ROS 2's builtin_interfaces/Time: int32 sec (the glue stores (int)ros_time_sec()), uint32 nanosec
    ros2 = f"{path}.nanosec" in {str(p) for p in model.leaf_paths(t.msg_type)}
    nsec = "nanosec" if ros2 else "nsec"
    if src is None:
        sec = f"(int)\\old({STAMP_SEC})" if ros2 else f"\\old({STAMP_SEC})"
        return {f"{path}.sec": sec, f"{path}.{nsec}": f"\\old({STAMP_NSEC})"}
    src_c, src_path = src
    base = f"{next(s for s in model.subscribed if s.c_name == src_c).msg_var}.{'.'.join(src_path)}"
    return {f"{path}.{f}": f"\\old({base}.{f})" for f in ("sec", nsec)}


def _globals(model: NodeModel) -> list[tuple[str, str]]:
    """(declaration, name) of every global of the glue (and, with a timed
    topic, of :data:`CLOCK`; with a topic stamped with the cycle's time,
    of :data:`STAMP_SEC` and :data:`STAMP_NSEC`)."""
    c = model.controller
    out = [(f"struct {c.inputs.struct_name} {c.inputs.var_name}", c.inputs.var_name),
           (f"struct {c.outputs.struct_name} {c.outputs.var_name}", c.outputs.var_name)]
    out += [(f"struct {t.msg_struct} {t.msg_var}", t.msg_var) for t in model.subscribed]
    for t in model.timed_topics:
        out += [(f"unsigned long long {t.time_var}", t.time_var), (f"unsigned char {t.new_var}", t.new_var),
                (f"unsigned char {t.rcvd_var}", t.rcvd_var)]
    if model.timed_topics:
        out.append((f"unsigned long long {CLOCK}", CLOCK))
    if _stamps_now(model):
        out += [(f"unsigned int {STAMP_SEC}", STAMP_SEC), (f"unsigned int {STAMP_NSEC}", STAMP_NSEC)]
    return out


def _age(t) -> str:
    """The age in ns of timed topic ``t`` at the time ``input_glue`` reads
    (a term of mathematical integers over the state before the call)."""
    now, time_ = f"\\old({CLOCK})", f"\\old({t.time_var})"
    return f"(\\old({t.rcvd_var}) != 0 ? ({time_} <= {now} ? {now} - {time_} : 0) : {_NO_AGE})"


def _c_float(prim: str, bits: int) -> str:
    """The exact C literal of a float fallback (hexadecimal)."""
    import struct

    if prim == "float32":
        x = struct.unpack("<f", struct.pack("<I", bits))[0]
        return x.hex() + "f"
    return struct.unpack("<d", struct.pack("<Q", bits))[0].hex()


def fallback_constants(model: NodeModel) -> list[tuple[str, str]]:
    """(declaration with its initialiser, name) of the ``static const``
    globals holding the float fallbacks, one per input."""
    out = []
    for r in model.input_relations:
        fb = r.fallback
        if fb is not None and r.path.prim in _BOXES:
            name = f"rosgen_wp_fallback_{r.input_field}"
            out.append((f"static const {_BOXES[r.path.prim].c_type} {name} = {_c_float(r.path.prim, fb.n)}", name))
    return out


def contracts(model: NodeModel) -> list[Contract]:
    """The contracts of the callbacks, ``input_glue`` and the output glues,
    in the order of the glue."""
    globs = [name for _, name in _globals(model)] + [b.var for b in _BOXES.values()]
    timed = {t.name for t in model.timed_topics}
    out: list[Contract] = []
    u = model.controller.inputs
    for t in model.subscribed:
        sep = tuple(f"&{g}" for g in globs)
        read = model.read_leaves(t)
        direct = model.direct_relations(t)
        ens = tuple(_same(p.prim, p.c_access(t.msg_var), f"\\old({p.c_access('msg', arrow=True)})")
                    for p in read)
        # rule 4.16: the direct relations, from *msg into the controller's inputs
        ens += tuple(_same(r.path.prim, f"{u.var_name}.{r.input_target}",
                           f"\\old({r.path.c_access('msg', arrow=True)})") for r in direct)
        clock = ((f"{t.time_var} == \\old({CLOCK})", f"{t.new_var} == 1", f"{t.rcvd_var} == 1")
                 if t.name in timed else ())
        assigns = (*(p.c_access(t.msg_var) for p in read),
                   *(f"{u.var_name}.{r.input_target}" for r in direct),
                   *((t.time_var, t.new_var, t.rcvd_var) if t.name in timed else ()))
        valid = dict.fromkeys(p.c_access("msg", arrow=True) for p in (*read, *(r.path for r in direct)))
        out.append(Contract(
            name=t.callback,
            proto=f"void {t.callback}(struct {t.msg_struct} *msg)",
            requires=("\\valid_read(msg)", f"\\separated(msg, {', '.join(sep)})",
                      *(f"\\valid_read(&{a})" for a in valid)),
            assigns=assigns or ("\\nothing",),
            ensures=ens + clock, pointer="msg", separated=sep))
    ens, assigned = [], []
    for r in model.glue_relations:  # rule 4.16: the direct ones are the callbacks'
        dst = f"{u.var_name}.{r.input_target}"  # Controller_U.In1, Controller_U.Scan[540] (rule 4.15)
        assigned.append(dst)
        same = _same(r.path.prim, dst, f"\\old({r.path.c_access(r.topic.msg_var)})")
        fb = r.fallback
        if fb is not None and r.topic.timeout_ms is not None:
            value = (f"rosgen_wp_fallback_{r.input_field}" if r.path.prim in _BOXES else str(fb.n))
            ens.append(f"({r.topic.timeout_ms * 1000000} < {_age(r.topic)} ? {_same(r.path.prim, dst, value)} "
                       f": {same})")
        else:
            ens.append(same)
    for r in model.derived_relations:
        dst = f"{u.var_name}.{r.input_field}"
        assigned.append(dst)
        if r.kind == "is_new":
            ens.append(f"{dst} == \\old({r.topic.new_var})")
        elif r.kind == "received":
            ens.append(f"{dst} == \\old({r.topic.rcvd_var})")
        else:
            a = _age(r.topic)
            ens.append(f"{dst} == ({a} <= {_MAX_AGE} ? {a} / 1000000 : 4294967295)")
    for t in model.timed_topics:
        assigned.append(t.new_var)
        ens.append(f"{t.new_var} == 0")
    out.append(Contract(name="input_glue", proto="void input_glue(void)", requires=(),
                        assigns=tuple(assigned) or ("\\nothing",), ensures=tuple(ens)))
    y = model.controller.outputs
    for t in model.published:
        rels = {str(r.path): r for r in model.output_relations_of(t)}
        consts = _string_leaves(t)
        stamp = _stamp_values(model, t)
        ens = []
        for p in model.leaf_paths(t.msg_type):
            leaf = p.c_access("command", arrow=True)
            r = rels.get(str(p))
            if r is not None:
                ens.append(_same(p.prim, leaf, f"\\old({y.var_name}.{r.output_source})"))
            elif str(p) in stamp:
                ens.append(_same(p.prim, leaf, stamp[str(p)]))
            else:
                ens.append(_same(p.prim, leaf, consts.get(str(p), _zero(p.prim))))
        sep = tuple(f"&{g}" for g in globs)
        out.append(Contract(
            name=t.output_glue,
            proto=f"void {t.output_glue}(struct {t.msg_struct} *command)",
            requires=("\\valid(command)", f"\\separated(command, {', '.join(sep)})",
                      *(f"\\valid(&{p.c_access('command', arrow=True)})" for p in model.leaf_paths(t.msg_type))),
            assigns=("*command",), ensures=tuple(ens), pointer="command", separated=sep))
    return out


def render_wrapper(model: NodeModel, glue_name: str, header_name: str,
                   contract_list: list[Contract] | None = None) -> str:
    """The WP wrapper: the contracts, then ``#include`` of the glue."""
    cs = contracts(model) if contract_list is None else contract_list
    return render("wp_contracts.c.j2",
        template=WRAPPER_TEMPLATE, source=source_label(Path(model.source).name), header=header_name,
        glue=glue_name, externs=_globals(model), boxes=list(_BOXES.values()), functions=cs,
        clock=CLOCK if model.timed_topics else None, constants=fallback_constants(model),
        stamp=(STAMP_SEC, STAMP_NSEC) if _stamps_now(model) else None)


# ---------------------------------------------------------------------------
# Running Frama-C

_PROVED = re.compile(r"^\[wp\] Proved goals:\s+(\d+)\s*/\s*(\d+)\s*$", re.M)
_GOAL = re.compile(r"^\[wp\] \[(?P<prover>[^\]]+)\] Goal (?P<goal>\S+) : (?P<status>\w+)", re.M)
_UNPROVED = re.compile(r"^\[wp\] (?:\[(?P<prover>[^\]]+)\] )?Goal (?P<goal>\S+) : (?P<status>.*)$", re.M)
_HYPS = re.compile(r"Memory model hypotheses for function '(?P<fn>\w+)':(?P<body>.*?)void \w+\(", re.S)
_SEPARATED = re.compile(r"\\separated\(([^;]*)\);")
_BY_PROVER = re.compile(r"^\s+(Qed|[A-Z][\w-]*(?: [\d.]+)?):\s+(\d+)", re.M)


def _tool(name: str, hint: str) -> str:
    path = shutil.which(name)
    if path is None:
        raise WPError(f"{name} not found: {hint}")
    return path


def _why3_config(work: Path) -> tuple[Path, tuple[str, ...]]:
    """A private Why3 configuration (``why3 config detect``) and the
    provers of :data:`PROVERS` it found."""
    why3 = _tool("why3", "install why3 (Debian package why3) for --wp")
    conf = work / "why3.conf"
    proc = subprocess.run([why3, "config", "detect", "-C", str(conf)], capture_output=True, text=True,
                          check=False, timeout=300, cwd=str(work))
    if proc.returncode != 0 or not conf.is_file():
        raise WPError("why3 config detect failed", [ln for ln in (proc.stdout + proc.stderr).splitlines()[-5:]])
    text = conf.read_text(errors="replace")
    found = tuple(p for p in PROVERS if re.search(rf'^name = "{re.escape(_WHY3_NAMES[p])}"', text, re.M))
    if not found:
        raise WPError("no SMT prover found by why3 (install z3 or alt-ergo) for --wp")
    return conf, found


def memory_hypotheses(output: str) -> list[tuple[str, tuple[str, ...]]]:
    """The memory-model hypotheses WP reports: (function, terms of each
    ``\\separated(...)``)."""
    out = []
    for m in _HYPS.finditer(output):
        for sep in _SEPARATED.findall(m.group("body")):
            out.append((m.group("fn"), tuple(t.strip() for t in sep.replace("\n", " ").split(","))))
    return out


def _check_hypotheses(output: str, cs: list[Contract] | list[tuple[str, str | None, tuple[str, ...]]]) -> None:
    """Every memory-model hypothesis WP reports must be stated in the
    contract (``cs``: the contracts, or their (name, pointer, separated))."""
    by_name = {c[0]: c for c in (contract_frame(c) if isinstance(c, Contract) else c for c in cs)}
    for fn, terms in memory_hypotheses(output):
        c = by_name.get(fn)
        pointer, separated = (c[1], c[2]) if c is not None else (None, ())
        stated = set(separated) | {pointer} if pointer else set()
        if c is None or pointer not in terms or not set(terms) <= stated:
            raise WPError(f"WP assumed a memory-model hypothesis that the contract of {fn} does not "
                          f"state: \\separated({', '.join(terms)})")


def contract_frame(c: Contract) -> tuple[str, str | None, tuple[str, ...]]:
    """What a WP run needs of a contract besides its text in the contracts
    file: its function, pointer argument and stated separations."""
    return (c.name, c.pointer, tuple(c.separated))


def run_wp(model: NodeModel, glue: str | Path, header: str | Path, work: str | Path, *,
           timeout: int = 10, jobs: int = 2, provers: tuple[str, ...] | None = None,
           functions: tuple[str, ...] | None = None) -> WPResult:
    """Prove the contracts of :func:`contracts` on the printed ``glue`` (which
    includes ``header``) with Frama-C WP, in the directory ``work``; only
    those of ``functions`` if given (every function otherwise).

    Raises :class:`WPError` unless every goal is proved."""
    _tool("frama-c", "install Frama-C (Debian package frama-c-base) for --wp")
    work = Path(work)
    work.mkdir(parents=True, exist_ok=True)
    glue, header = Path(glue), Path(header)
    for f in (glue, header):
        if f.resolve().parent != work.resolve():
            shutil.copyfile(f, work / f.name)
    cs = contracts(model)
    wrapper = work / f"{model.name}_wp.c"
    wrapper.write_text(render_wrapper(model, glue.name, header.name, cs), encoding="ascii")
    frames = [contract_frame(c) for c in cs if functions is None or c.name in functions]
    if functions is not None and {f[0] for f in frames} != set(functions):
        raise ValueError(f"no contract for {sorted(set(functions) - {f[0] for f in frames})}")
    return run_wp_file(wrapper, frames, timeout=timeout, jobs=jobs, provers=provers)


def run_wp_file(wrapper: Path, frames: list[tuple[str, str | None, tuple[str, ...]]], *,
                timeout: int = 10, jobs: int = 2, provers: tuple[str, ...] | None = None,
                limit: float = 3600.0) -> WPResult:
    """Prove the contracts of the contracts file ``wrapper`` (which
    includes the glue and its header, next to it) on the functions of
    ``frames`` (:func:`contract_frame`); the folder of ``wrapper`` is the
    work folder.  Raises :class:`WPError` unless every goal is proved and
    every memory-model hypothesis WP used is stated by a contract.
    ``timeout`` is WP's limit per goal; ``limit`` stops Frama-C as a whole
    after that many seconds (``verify --timeout``)."""
    frama_c = _tool("frama-c", "install Frama-C (Debian package frama-c-base) for --wp")
    work = wrapper.parent
    conf, found = _why3_config(work)
    use = tuple(p for p in (provers or found) if p in found)
    if not use:
        raise WPError(f"none of the provers {', '.join(provers or ())} is installed")
    argv = [frama_c, "-no-autoload-plugins", "-load-module", "wp",
            "-wp", "-wp-rte", "-wp-model", "Typed+float", "-wp-prover", ",".join(use),
            "-wp-timeout", str(timeout), "-wp-par", str(jobs),
            "-wp-fct", ",".join(f[0] for f in frames), "-wp-session", str(work / "wp-session"),
            wrapper.name]
    # Frama-C resolves relative file names against $PWD, not the process's cwd
    env = dict(os.environ, WHY3CONFIG=str(conf), PWD=str(work.resolve()))
    t0 = time.monotonic()
    try:
        proc = procs.run(argv, cwd=work, env=env, timeout=limit)
    except subprocess.TimeoutExpired:
        raise WPError(f"frama-c did not finish within {limit:g} s") from None
    seconds = time.monotonic() - t0
    output = proc.stdout + proc.stderr
    m = _PROVED.search(output)
    if proc.returncode != 0 or m is None:
        tail = [ln for ln in output.splitlines() if "rror" in ln or "abort" in ln][:10]
        raise WPError(f"frama-c failed (exit status {proc.returncode})", tail or output.splitlines()[-10:])
    proved, total = int(m.group(1)), int(m.group(2))
    by_prover = {k: int(v) for k, v in _BY_PROVER.findall(output[m.end():])}
    result = WPResult(proved, total, seconds, use, tuple(f[0] for f in frames), wrapper, output, by_prover)
    if not result.ok:
        bad = [f"  {g.group('goal')}: {g.group('status').strip()}" for g in _UNPROVED.finditer(output)
               if not g.group("status").startswith(("Valid", "trivial"))]
        raise WPError(f"Frama-C WP: {proved}/{total} goals proved, not all", bad[:20])
    _check_hypotheses(output, frames)
    return result
