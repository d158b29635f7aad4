"""Rule 4.11: a controller written as a block diagram.

The optional keys ``controller.blocks`` and ``controller.outports`` of a
node model describe the controller as a diagram of Simulink-style blocks
instead of C brought by the user (DESIGN.md rule 4.11;
``coq/theories/ctrl/Diagram.v`` says what a diagram means, and Coq checks
the emitted diagram again with ``Diagram.dg_wf``).  :func:`check_diagram`
checks every part of it, reporting each problem at its place, infers the
type of every signal, orders the blocks for evaluation and names any
algebraic loop; it returns the :class:`~pyrosgen.frontend.model.Diagram`
when the diagram is valid.
"""

from __future__ import annotations

import heapq
import re
from collections import deque
from dataclasses import dataclass, field
from fractions import Fraction

from pyrosgen.errors import show
from pyrosgen.frontend import ieee, subsystems
from pyrosgen.frontend.model import (
    BLOCK_KINDS, SIGNAL_TYPES, Block, ControllerField, Diagram, Pos, Scalar,
)
from pyrosgen.frontend.names import MAX_NAME_LEN, did_you_mean, identifier_problem
from pyrosgen.frontend.subsystems import SUBSYSTEM
from pyrosgen.frontend.yamlsrc import YBad, YMap, YNode, YScalar, YSeq

__all__ = ["check_diagram", "MAX_BLOCKS", "MAX_BLOCK_NAME", "INT_RANGES", "scalar_of"]

RULE = "4.11"

#: At most this many blocks in a diagram (DESIGN.md rule 4.11).
MAX_BLOCKS = 5000

#: Longest block name: its C temporary ``rtb_<name>`` has at most 63
#: characters (rule 4.9).
MAX_BLOCK_NAME = MAX_NAME_LEN - len("rtb_")

#: The range of each integer signal type.
INT_RANGES = {
    "int32": (-(1 << 31), (1 << 31) - 1),
    "uint32": (0, (1 << 32) - 1),
    "int64": (-(1 << 63), (1 << 63) - 1),
    "uint64": (0, (1 << 64) - 1),
}
FLOAT_TYPES = ("float32", "float64")
NUMERIC_TYPES = tuple(t for t in SIGNAL_TYPES if t != "bool")

#: The keys of each block kind besides ``name`` and ``block``:
#: (required, optional).
KEYS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "Constant": (("value", "type"), ()),
    "Gain": (("input", "gain"), ()),
    "Sum": (("inputs",), ("signs",)),
    "Product": (("inputs",), ()),
    "Divide": (("inputs",), ()),
    "Abs": (("input",), ()),
    "MinMax": (("function", "inputs"), ()),
    "Saturation": (("input", "lower", "upper"), ()),
    "RelationalOperator": (("operator", "inputs"), ()),
    "Logic": (("operator", "inputs"), ()),
    "Switch": (("inputs", "criterion"), ("threshold",)),
    "UnitDelay": (("input",), ("initial", "type")),
    "DiscreteIntegrator": (("input",), ("gain", "initial", "lower", "upper", "method")),
}
assert tuple(KEYS) == BLOCK_KINDS

_FLOAT_ONLY = ("Divide", "Abs", "DiscreteIntegrator")

#: RelationalOperator operators (``~=`` is MATLAB's ``!=``).
RELOPS = {"==": "==", "~=": "!=", "!=": "!=", "<": "<", "<=": "<=", ">": ">", ">=": ">="}
LOGIC_OPS = ("AND", "OR", "NAND", "NOR", "XOR", "NOT")
CRITERIA = ("u2 >= threshold", "u2 > threshold", "u2 ~= 0")
METHODS = ("ForwardEuler",)

#: A YAML 1.1 plain scalar that looks like a number but is read as text
#: (``1e-3``: YAML 1.1 wants a dot and a signed exponent).
_NUMBER_LIKE = re.compile(r"[-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)[eE][-+]?[0-9]+")


def _list(names) -> str:
    return ", ".join(names)


def _a(kind: str) -> str:
    """``a Gain``, ``an Abs``."""
    return f"an {kind}" if kind[0] in "AEIOU" else f"a {kind}"


@dataclass
class _B:
    """A block as far as it could be checked."""

    index: int
    node: YMap
    what: str
    name: str | None = None
    name_node: YNode | None = None
    kind: str | None = None
    refs: list[tuple[str, YNode]] = field(default_factory=list)  # input signals and their nodes
    refs_node: YNode | None = None   # the `input` or `inputs` node
    broken: bool = False             # a problem of its own was reported
    declared: str | None = None      # Constant's / UnitDelay's `type`
    op: str | None = None
    signs: str | None = None
    prim: str | None = None          # inferred output type
    input_prim: str | None = None

    def get(self, key: str) -> YNode | None:
        v = self.node.get(key)
        return None if isinstance(v, YBad) else v

    @property
    def is_state(self) -> bool:
        return self.kind in ("UnitDelay", "DiscreteIntegrator")


class _DiagramChecker:
    def __init__(self, ck, cm: YMap, ctrl_name, ufields, yfields, uvar, yvar, period):
        self.ck = ck
        self.cm = cm
        self.ctrl_name = ctrl_name
        self.ufields = ufields
        self.yfields = yfields
        self.uvar = uvar
        self.yvar = yvar
        self.period = period
        self.start = len(ck.diags)
        self.pending: list | None = None      # collected, not yet reported, problems
        self.tainted: set[str] = set()        # blocks with a type error and what reads them
        self.bad_names: set[str] = set()      # names of blocks refused (not reported as unknown signals)

    # -- reporting -------------------------------------------------------------

    @property
    def errors(self) -> int:
        """How many problems the diagram has (every one is reported
        through the checker, here or by its helpers)."""
        return len(self.ck.diags) - self.start

    def err(self, where, message: str) -> None:
        if self.pending is not None:
            self.pending.append((where, message))
        else:
            self.ck.err_rule(RULE, where, message)

    # -- values ------------------------------------------------------------------

    def scalar(self, node: YNode | None, prim: str, what: str) -> Scalar | None:
        """A constant of type ``prim`` written at ``node``, or ``None``
        (reported) when it is not one."""
        if node is None or isinstance(node, YBad):
            return None
        s, problem = scalar_of(node, prim)
        if problem:
            self.err(node, f"{what}: {problem}")
        return s

    # -- the whole -----------------------------------------------------------------

    def run(self) -> Diagram | None:
        cm = self.cm
        bnode, onode = cm.get("blocks"), cm.get("outports")
        if bnode is None and cm.get("subsystems") is not None:
            self.err(cm.key_node("subsystems"), "controller.subsystems without controller.blocks: subsystems "
                     "are instantiated by Subsystem blocks of a block diagram; remove subsystems, or describe "
                     "the controller with blocks")
        if bnode is None and onode is None:
            return None
        if bnode is None:
            self.err(cm.key_node("outports"), "controller.outports without controller.blocks: outports "
                     "name the signals of a block diagram; remove outports, or describe the controller "
                     "with blocks")
            return None
        if onode is None:
            self.err(cm.key_node("blocks"), "controller.blocks without controller.outports: give "
                     "outports, the signal each controller output takes (Out1: <signal>)")
        if isinstance(bnode, YBad):
            return None
        if not isinstance(bnode, YSeq):
            self.err(bnode, f"controller.blocks must be a list of blocks, got {bnode.describe()}")
            return None
        if not bnode.items:
            self.err(bnode, "controller.blocks must list at least one block (or remove blocks and "
                     "outports to bring the controller as C)")
            return None
        if len(bnode.items) > MAX_BLOCKS:
            self.err(bnode, f"controller.blocks lists {len(bnode.items)} blocks; a diagram has at "
                     f"most {MAX_BLOCKS}")
            return None

        interface = self.ufields is not None and self.yfields is not None
        self.inputs = {f.name: (k, f) for k, f in self.ufields} if self.ufields is not None else {}
        self.outputs = {f.name: (k, f) for k, f in self.yfields} if self.yfields is not None else {}

        # Subsystem blocks, replaced by the blocks of their subsystems
        # (a front-end expansion: what follows sees ordinary blocks only)
        expansion = subsystems.expand(
            self.err, self.ck.string, cm, bnode, onode, {n: k for n, (k, _) in self.inputs.items()},
            self.bad_names, limit=MAX_BLOCKS, max_name=MAX_BLOCK_NAME)
        if expansion is None:
            return None
        onode = expansion.outports
        blocks = [self.parse_block(i, item.node, item.where, item.quiet) for i, item in enumerate(expansion.items)]
        blocks = [b for b in blocks if b is not None]
        # names: each signal driven once
        self.by_name: dict[str, _B] = {}
        for b in blocks:
            if b.name is None:
                continue
            if b.name in self.inputs:
                knode, _ = self.inputs[b.name]
                self.err(b.name_node, f"{b.what}: signal {show(b.name)} is driven twice: by this block "
                         f"and by controller input {show(b.name)} (line {knode.line})")
                b.broken = True
                b.name = None
            elif b.name in self.by_name:
                first = self.by_name[b.name]
                self.err(b.name_node, f"{b.what}: signal {show(b.name)} is driven twice: by this block "
                         f"and by {first.what} (line {first.name_node.line})")
                b.broken = True
                b.name = None
            else:
                self.by_name[b.name] = b
        self.blocks = blocks
        if not interface:
            # the controller's inputs or outputs are broken (reported under
            # rule 4.3): which signal exists is unknown
            self.outports_structure(onode)
            return None
        self.interface_types()
        self.resolve_refs()
        self.infer_types()
        self.check_types()
        self.parameters()
        loops = self.algebraic_loops()
        outports = self.outports(onode)
        used = self.used_inports(outports)
        self.c_temporaries(used)
        if (self.errors or outports is None or loops or self.period is None
                or self.unknown or any(b.broken or b.kind is None for b in blocks)):
            return None   # every problem was reported (here, or by the YAML reader)
        order = self.topological_order()
        return Diagram(
            blocks=tuple(self.final(b) for b in blocks),
            inports=tuple(f for _, f in self.ufields if f.name in used),
            outports=tuple(outports),
            order=tuple(order),
            period_ms=self.period,
        )

    # -- one block -----------------------------------------------------------------

    def parse_block(self, i: int, item: YNode, where: str, quiet: bool = False) -> _B | None:
        """The block ``i`` of the (expanded) diagram, written at ``where``
        (``controller.blocks[3]``, or the block of a subsystem that it
        copies); ``quiet``: a later copy of a subsystem's block, whose
        problems of shape were reported with the first copy (they are the
        same)."""
        start = len(self.ck.diags)
        try:
            return self.parse_one(i, item, where)
        finally:
            if quiet:
                del self.ck.diags[start:]

    def parse_one(self, i: int, item: YNode, what: str) -> _B | None:
        if isinstance(item, YBad):
            return None
        if not isinstance(item, YMap):
            self.err(item, f"{what} must be a mapping (name: ..., block: ..., ...), got {item.describe()}")
            return None
        b = _B(i, item, what)
        # name
        nnode = item.get("name")
        b.name_node = nnode if nnode is not None else item
        name = self.ck.string(nnode, f"{what}.name") if nnode is not None else None
        if nnode is None:
            self.err(item.owner_pos, f"{what}: missing key 'name' (the block's output signal)")
            b.broken = True
        elif name is None:
            b.broken = True
        else:
            problem = identifier_problem(name, global_scope=True)
            if problem is None and len(name) > MAX_BLOCK_NAME:
                problem = (f"it is longer than {MAX_BLOCK_NAME} characters ({len(name)}; its C temporary "
                           "is rtb_<name>)")
            if problem:
                self.err(nnode, f"{what}.name: block name {show(name)} cannot be used: {problem}")
                self.bad_names.add(name)
                b.broken = True
            else:
                b.name = name
                b.what = f"{what} ({name})"
        what = b.what
        # kind
        knode = item.get("block")
        if knode is None:
            self.err(item.owner_pos, f"{what}: missing key 'block' (the block's kind: "
                     f"{_list(BLOCK_KINDS + (SUBSYSTEM,))})")
            b.broken = True
            return b
        kind = self.ck.string(knode, f"{what}.block")
        if kind is None:
            b.broken = True
            return b
        if kind not in KEYS:
            self.err(knode, f"{what}: unknown block kind {show(kind)}{did_you_mean(kind, BLOCK_KINDS + (SUBSYSTEM,))}; "
                     f"expected one of {_list(BLOCK_KINDS + (SUBSYSTEM,))}")
            b.broken = True
            return b
        b.kind = kind
        # keys
        required, optional = KEYS[kind]
        allowed = ("name", "block") + required + optional
        for k in item.keys():
            if k not in allowed:
                self.err(item.key_node(k), f"{what}: {_a(kind)} block has no key {show(k)}"
                         f"{did_you_mean(k, allowed)}; its keys are {_list(allowed)}")
                b.broken = True
        for k in item.keys():
            if isinstance(item.get(k), YBad):
                # refused by the YAML reader (a number spelling of rule
                # 4.1, a tag, ...), which reported it: the block is not
                # checked further, and no diagram is built
                b.broken = True
        for k in required:
            if item.get(k) is None:
                self.err(item.owner_pos, f"{what}: missing key {show(k)} ({_a(kind)} block needs "
                         f"{_list(required)})")
                b.broken = True
        # inputs
        if "input" in required:
            self.single_input(b)
        elif "inputs" in required:
            self.input_list(b)
        # kind-specific keys that do not depend on types
        getattr(self, f"shape_{kind}", lambda b: None)(b)
        return b

    def single_input(self, b: _B) -> None:
        node = b.node.get("input")
        if node is None or isinstance(node, YBad):
            b.broken = b.broken or isinstance(node, YBad)
            return
        b.refs_node = node
        if isinstance(node, YSeq):
            self.err(node, f"{b.what}.input must be one signal name; {_a(b.kind)} block has one input")
            b.broken = True
            return
        s = self.ck.string(node, f"{b.what}.input")
        if s is None:
            b.broken = True
            return
        b.refs = [(s, node)]

    def input_list(self, b: _B) -> None:
        node = b.node.get("inputs")
        if node is None or isinstance(node, YBad):
            b.broken = b.broken or isinstance(node, YBad)
            return
        b.refs_node = node
        if not isinstance(node, YSeq):
            self.err(node, f"{b.what}.inputs must be a list of signal names, got {node.describe()}")
            b.broken = True
            return
        refs = []
        for k, item in enumerate(node.items):
            s = self.ck.string(item, f"{b.what}.inputs[{k}]") if not isinstance(item, YBad) else None
            if s is None:
                continue
            refs.append((s, item))
        b.refs = refs
        if len(refs) != len(node.items):
            b.broken = True
            return
        n = len(refs)
        arity = {
            "Sum": (1, None, "at least one input"),
            "MinMax": (1, None, "at least one input"),
            "Product": (2, 2, "2 inputs [a, b]"),
            "Divide": (2, 2, "2 inputs [a, b] (a / b)"),
            "RelationalOperator": (2, 2, "2 inputs [a, b] (a <operator> b)"),
            "Switch": (3, 3, "3 inputs [a, control, b] (a when the control input passes the criterion, else b)"),
        }.get(b.kind)
        if arity is not None:
            lo, hi, text = arity
            if n < lo or (hi is not None and n > hi):
                self.err(node, f"{b.what}: {_a(b.kind)} block takes {text}, got {n}")
                b.broken = True

    # -- kind-specific shapes ------------------------------------------------------

    def enum(self, b: _B, key: str, choices, describe: str) -> str | None:
        node = b.get(key)
        if node is None:
            return None
        if isinstance(node, YScalar) and node.kind == "str" and node.value == "":
            self.err(node, f"{b.what}.{key} is empty (a bare '>' starts a folded text in YAML: quote "
                     f"the {describe}, e.g. '>')")
            b.broken = True
            return None
        s = self.ck.string(node, f"{b.what}.{key}")
        if s is None:
            b.broken = True
            return None
        if s not in choices:
            hint = did_you_mean(s, choices)
            if not hint and s.upper() in choices:
                hint = f" (did you mean {show(s.upper())}?)"
            self.err(node, f"{b.what}.{key}: unknown {describe} {show(s)}{hint}; expected "
                     f"{_list(repr(c) if ' ' in c else c for c in choices)}")
            b.broken = True
            return None
        return s

    def declared_type(self, b: _B) -> None:
        node = b.get("type")
        if node is None:
            return
        t = self.ck.string(node, f"{b.what}.type")
        if t is None:
            b.broken = True
            return
        if t not in SIGNAL_TYPES:
            self.err(node, f"{b.what}.type: {show(t)} is not a signal type{did_you_mean(t, SIGNAL_TYPES)}; "
                     f"a diagram's signals are {_list(SIGNAL_TYPES)}")
            b.broken = True
            return
        b.declared = t

    def shape_Constant(self, b: _B) -> None:
        self.declared_type(b)

    def shape_UnitDelay(self, b: _B) -> None:
        self.declared_type(b)

    def shape_Sum(self, b: _B) -> None:
        node = b.get("signs")
        if node is None:
            if b.refs and not b.broken:
                b.signs = "+" * len(b.refs)
            return
        s = self.ck.string(node, f"{b.what}.signs")
        if s is None:
            b.broken = True
            return
        if not re.fullmatch(r"[+-]+", s):
            self.err(node, f"{b.what}.signs must be a string of '+' and '-', one per input, got {show(s)}")
            b.broken = True
            return
        if b.refs and not b.broken and len(s) != len(b.refs):
            self.err(node, f"{b.what}.signs has {len(s)} signs for {len(b.refs)} inputs; give one sign per input")
            b.broken = True
            return
        b.signs = s

    def shape_MinMax(self, b: _B) -> None:
        b.op = self.enum(b, "function", ("min", "max"), "function")

    def shape_RelationalOperator(self, b: _B) -> None:
        op = self.enum(b, "operator", tuple(RELOPS), "operator")
        b.op = RELOPS[op] if op is not None else None

    def shape_Logic(self, b: _B) -> None:
        b.op = self.enum(b, "operator", LOGIC_OPS, "operator")
        if b.op is None or b.broken or b.refs_node is None:
            return
        n = len(b.refs)
        if b.op == "NOT" and n != 1:
            self.err(b.refs_node, f"{b.what}: a Logic block with operator NOT takes exactly 1 input, got {n}")
            b.broken = True
        elif b.op != "NOT" and n < 2:
            self.err(b.refs_node, f"{b.what}: a Logic block with operator {b.op} takes at least 2 inputs, got {n}")
            b.broken = True

    def shape_Switch(self, b: _B) -> None:
        b.op = self.enum(b, "criterion", CRITERIA, "criterion")
        if b.op is None:
            return
        tnode = b.node.get("threshold")
        if b.op == "u2 ~= 0" and tnode is not None:
            self.err(b.node.key_node("threshold"), f"{b.what}: criterion 'u2 ~= 0' takes no threshold")
            b.broken = True
        elif b.op != "u2 ~= 0" and tnode is None:
            self.err(b.node.owner_pos, f"{b.what}: missing key 'threshold' (criterion {show(b.op)} compares "
                     "the control input with it)")
            b.broken = True

    def shape_DiscreteIntegrator(self, b: _B) -> None:
        if b.get("method") is not None:
            if self.enum(b, "method", METHODS, "integration method") is None:
                return
        has_lo, has_hi = b.node.get("lower") is not None, b.node.get("upper") is not None
        if has_lo != has_hi:
            present, absent = ("lower", "upper") if has_lo else ("upper", "lower")
            self.err(b.node.key_node(present), f"{b.what}: {present} without {absent}: give both limits "
                     "or neither")
            b.broken = True

    # -- signals -------------------------------------------------------------------

    def resolve_refs(self) -> None:
        """Every input names a signal: a block or a controller input of a
        signal type."""
        signals = list(self.inputs) + list(self.by_name)
        self.unknown: set[int] = set()   # blocks reading an unknown or unusable signal
        for b in self.blocks:
            for k, (s, node) in enumerate(b.refs):
                if s in self.by_name or s in self.inputs:
                    if s in self.inputs and self.inputs[s][1].prim not in SIGNAL_TYPES:
                        self.unknown.add(b.index)    # reported at the field (interface_types)
                    continue
                self.unknown.add(b.index)
                if s in self.bad_names:
                    continue                  # the block's name was refused: reported there
                hint = did_you_mean(s, signals)
                if s in self.outputs:
                    hint = f" ({show(s)} is a controller output; signals are the blocks and the controller inputs)"
                self.err(node, f"{b.what}: unknown signal {show(s)}{hint}")

    def interface_types(self) -> None:
        """Every field of the controller's inputs and outputs has a signal
        type (``Diagram.dg_wf``: the diagram's C declares the structs, and
        computes on these types only)."""
        for kind, fields in (("input", self.ufields), ("output", self.yfields)):
            for knode, f in fields:
                if f.prim not in SIGNAL_TYPES:
                    self.err(knode, f"controller {kind} {show(f.name)} is {f.prim}: the inputs and outputs of a "
                             f"controller written as a block diagram have the signal types "
                             f"{_list(SIGNAL_TYPES)}")

    def input_type(self, s: str) -> str | None:
        if s in self.inputs:
            p = self.inputs[s][1].prim
            return p if p in SIGNAL_TYPES else None
        b = self.by_name.get(s)
        return b.prim if b is not None else None

    def infer_types(self) -> None:
        """Types flow from the constants, the inports and the declared
        delays along the blocks, by a work list (delays in feedback loops
        get their type from their input when it is known)."""
        readers: dict[str, list[_B]] = {}
        for b in self.blocks:
            for s, _ in b.refs:
                readers.setdefault(s, []).append(b)
        work = deque()

        def settle(b: _B, prim: str | None) -> None:
            if prim is not None and b.prim is None:
                b.prim = prim
                if b.name is not None:
                    work.append(b.name)

        for b in self.blocks:
            if b.kind is None or (b.broken and b.kind != "Constant"):
                continue
            if b.kind == "Constant":
                settle(b, b.declared)
            elif b.kind in ("RelationalOperator", "Logic"):
                settle(b, "bool")
            elif b.kind == "UnitDelay" and b.declared:
                settle(b, b.declared)
        for name in self.inputs:
            work.append(name)
        while work:
            s = work.popleft()
            for b in readers.get(s, ()):
                if b.prim is not None or b.broken:
                    continue
                settle(b, self.rule_type(b))

    def rule_type(self, b: _B) -> str | None:
        refs = [s for s, _ in b.refs]
        if b.kind == "Switch":
            refs = [refs[0], refs[2]] if len(refs) == 3 else []
        for s in refs:
            t = self.input_type(s)
            if t is not None:
                return t
        return None

    def check_types(self) -> None:
        """Each block's inputs against its rule; a delay whose type is
        still unknown is named.  A block whose input comes (directly or
        not) from a block with a type error is not checked: its errors
        would only repeat the first one."""
        doubtful = self.doubtful()
        found: dict[str, list[tuple[object, str]]] = {}
        for b in self.blocks:
            if b.broken or b.kind is None:
                continue
            if b.prim is None:
                if b.is_state and b.name not in doubtful:
                    if b.kind == "UnitDelay":
                        self.err(b.name_node, f"{b.what}: cannot infer the type of this UnitDelay: its input "
                                 "is computed from its own output only, with no typed signal; give it a "
                                 "type (for example type: float64)")
                    else:
                        self.err(b.name_node, f"{b.what}: cannot infer the type of this DiscreteIntegrator: "
                                 "its input is computed from its own output only, with no typed signal; "
                                 "feed the loop from a typed signal (a Constant, an inport, or a UnitDelay "
                                 "with a type)")
                continue
            self.pending = []
            try:
                getattr(self, f"types_{b.kind}", self.types_same)(b)
            finally:
                mine, self.pending = self.pending, None
            if mine:
                found[b.name] = mine
        # Report a block's problems unless it reads (directly or not) a
        # block whose problems were reported: the first block with
        # problems in the model is always reported, so none goes unsaid.
        readers = self.readers()
        shadow: set[str] = set()
        for b in self.blocks:
            if b.name not in found or any(s in shadow for s, _ in b.refs):
                continue
            for where, message in found[b.name]:
                self.err(where, message)
            shadow.add(b.name)
            work = deque([b.name])
            while work:
                for r in readers.get(work.popleft(), ()):
                    if r.name is not None and r.name not in shadow:
                        shadow.add(r.name)
                        work.append(r.name)
        self.tainted = self.downstream(set(found))

    def readers(self) -> dict[str, list[_B]]:
        """The blocks that read each signal."""
        readers: dict[str, list[_B]] = {}
        for b in self.blocks:
            for s, _ in b.refs:
                readers.setdefault(s, []).append(b)
        return readers

    def downstream(self, names: set[str]) -> set[str]:
        """``names`` and every block that reads them, directly or not."""
        readers = self.readers()
        out = set(names)
        work = deque(names)
        while work:
            s = work.popleft()
            for b in readers.get(s, ()):
                if b.name is not None and b.name not in out:
                    out.add(b.name)
                    work.append(b.name)
        return out

    def doubtful(self) -> set[str]:
        """Signals whose type may be unknown because of a problem already
        reported: broken blocks, blocks reading an unknown signal, and
        what reads them."""
        return self.downstream({b.name for b in self.blocks
                                if b.name is not None and (b.broken or b.index in self.unknown)})

    def ref_types(self, b: _B, refs=None):
        """``(index, signal, node, type)`` of each input whose type is known."""
        out = []
        for k, (s, node) in enumerate(b.refs if refs is None else refs):
            t = self.input_type(s)
            if t is not None:
                out.append((k, s, node, t))
        return out

    def types_same(self, b: _B) -> None:
        """All inputs of the output's type (Gain, Sum, Product, Divide,
        Abs, MinMax, Saturation)."""
        typed = self.ref_types(b)
        if not typed:
            return
        k0, s0, _, t0 = typed[0]
        ok = True
        for k, s, node, t in typed[1:]:
            if t != t0:
                self.err(node, f"{b.what}: type mismatch: input {show(s)} is {t} but input {show(s0)} is "
                         f"{t0}; the inputs of {_a(b.kind)} block have one type")
                ok = False
        if ok:
            self.numeric(b, t0, typed[0][2])

    def numeric(self, b: _B, t: str, node) -> bool:
        if b.kind in _FLOAT_ONLY and t not in FLOAT_TYPES:
            self.err(node, f"{b.what}: {_a(b.kind)} block computes on float32 or float64; its input is {t}")
            return False
        if t == "bool":
            self.err(node, f"{b.what}: {_a(b.kind)} block computes on numbers; its input is bool")
            return False
        return True

    def types_Constant(self, b: _B) -> None:
        pass

    def types_DiscreteIntegrator(self, b: _B) -> None:
        for _, s, node, t in self.ref_types(b):
            self.numeric(b, t, node)

    def types_UnitDelay(self, b: _B) -> None:
        for _, s, node, t in self.ref_types(b):
            if b.declared and t != b.declared:
                self.err(node, f"{b.what}: type mismatch: input {show(s)} is {t} but this UnitDelay has "
                         f"type {b.declared}")

    def types_RelationalOperator(self, b: _B) -> None:
        typed = self.ref_types(b)
        if len(typed) < 2:
            return
        (_, sa, na, ta), (_, sb, nb, tb) = typed[0], typed[1]
        if ta != tb:
            self.err(nb, f"{b.what}: type mismatch: input {show(sb)} is {tb} but input {show(sa)} is {ta}; "
                     "a RelationalOperator block compares two values of one type")
        elif ta == "bool":
            self.err(na, f"{b.what}: a RelationalOperator block compares numbers; its inputs are bool (use a "
                     "Logic block)")
        else:
            b.input_prim = ta

    def types_Logic(self, b: _B) -> None:
        for _, s, node, t in self.ref_types(b):
            if t != "bool":
                self.err(node, f"{b.what}: type mismatch: input {show(s)} is {t} but a Logic block's inputs "
                         "are bool (compare it with a RelationalOperator first)")

    def types_Switch(self, b: _B) -> None:
        if len(b.refs) != 3:
            return
        (sa, na), (sc, nc), (sb, nb) = b.refs
        ta, tc, tb = self.input_type(sa), self.input_type(sc), self.input_type(sb)
        if ta is not None and tb is not None and ta != tb:
            self.err(nb, f"{b.what}: type mismatch: input {show(sb)} is {tb} but input {show(sa)} is {ta}; "
                     "a Switch passes one of two signals of one type")
        if tc is not None:
            if b.op != "u2 ~= 0" and tc == "bool":
                self.err(nc, f"{b.what}: control input {show(sc)} is bool; criterion {show(b.op)} compares "
                         "numbers (use criterion 'u2 ~= 0' for a bool)")
            else:
                b.input_prim = tc

    # -- parameters ----------------------------------------------------------------

    def parameters(self) -> None:
        """The constants of every typed block, read in its type."""
        self.values: dict[int, dict[str, Scalar]] = {}
        for b in self.blocks:
            if b.broken or b.kind is None:
                continue
            vals: dict[str, Scalar] = {}
            self.values[b.index] = vals
            q = b.prim
            w = b.what
            if b.kind == "Constant":
                if q is not None:
                    v = self.scalar(b.get("value"), q, f"{w}.value")
                    if v is not None:
                        vals["value"] = v
            elif b.kind == "Gain":
                if q in NUMERIC_TYPES:
                    v = self.scalar(b.get("gain"), q, f"{w}.gain")
                    if v is not None:
                        vals["gain"] = v
            elif b.kind == "Saturation":
                if q in NUMERIC_TYPES:
                    lo = self.scalar(b.get("lower"), q, f"{w}.lower")
                    hi = self.scalar(b.get("upper"), q, f"{w}.upper")
                    if lo is not None and hi is not None:
                        vals["lower"], vals["upper"] = lo, hi
                        if _num(lo) > _num(hi):
                            self.err(b.get("lower"), f"{w}: lower {lo.text} is above upper {hi.text}")
            elif b.kind == "Switch":
                if b.op != "u2 ~= 0" and b.input_prim in NUMERIC_TYPES:
                    v = self.scalar(b.get("threshold"), b.input_prim, f"{w}.threshold")
                    if v is not None:
                        vals["threshold"] = v
            elif b.kind == "UnitDelay":
                if q is not None:
                    node = b.get("initial")
                    v = self.scalar(node, q, f"{w}.initial") if node is not None else zero(q)
                    if v is not None:
                        vals["initial"] = v
            elif b.kind == "DiscreteIntegrator":
                if q in FLOAT_TYPES:
                    self.integrator(b, q, vals)

    def integrator(self, b: _B, q: str, vals: dict) -> None:
        w = b.what
        gnode = b.get("gain")
        gain = self.scalar(gnode, q, f"{w}.gain") if gnode is not None else scalar_of_text("1", q)
        inode = b.get("initial")
        init = self.scalar(inode, q, f"{w}.initial") if inode is not None else zero(q)
        lo = self.scalar(b.get("lower"), q, f"{w}.lower") if b.get("lower") is not None else None
        hi = self.scalar(b.get("upper"), q, f"{w}.upper") if b.get("upper") is not None else None
        if gain is not None:
            vals["gain"] = gain
            if self.period is not None:
                # kt = gain * T, T = period_ms / 1000 s, rounded once from
                # the exact product of the decimal gain and the period
                try:
                    kt = ieee.decimal_bits(gain.text, ieee.fmt(q), Fraction(self.period, 1000))
                except ieee.DecimalError:
                    self.err(gnode, f"{w}.gain: gain * sample time ({gain.text} * {self.period} / 1000) "
                             f"is out of the range of {q}")
                else:
                    vals["kt"] = Scalar(q, kt, f"{gain.text} * {self.period} / 1000")
        if init is not None:
            vals["initial"] = init
        if lo is not None and hi is not None:
            vals["lower"], vals["upper"] = lo, hi
            if _num(lo) > _num(hi):
                self.err(b.get("lower"), f"{w}: lower {lo.text} is above upper {hi.text}")
            elif init is not None and not _num(lo) <= _num(init) <= _num(hi):
                self.err(inode if inode is not None else b.get("lower"),
                         f"{w}: initial {init.text} is outside [lower, upper] = [{lo.text}, {hi.text}]")

    # -- loops and order -----------------------------------------------------------

    def edges(self) -> dict[str, list[str]]:
        """Data flow between blocks without memory: ``x -> b`` when ``b``
        reads ``x`` within the step."""
        succ: dict[str, list[str]] = {}
        for b in self.blocks:
            if b.name is None or b.is_state:
                continue
            for s, _ in b.refs:
                x = self.by_name.get(s)
                if x is not None and not x.is_state:
                    succ.setdefault(s, []).append(b.name)
        return succ

    def algebraic_loops(self) -> int:
        """Name every cycle of blocks not broken by a delay (one per
        strongly connected component), at its first block in the model."""
        succ = self.edges()
        nodes = [b.name for b in self.blocks if b.name is not None and not b.is_state]
        comps = _sccs(nodes, succ)
        found = 0
        index = {b.name: b.index for b in self.blocks if b.name is not None}
        for comp in comps:
            cset = set(comp)
            if len(comp) == 1 and comp[0] not in succ.get(comp[0], ()):
                continue
            start = min(comp, key=lambda n: index[n])
            cycle = _cycle_from(start, succ, cset)
            b = self.by_name[start]
            self.err(b.name_node, f"{b.what}: algebraic loop: {' -> '.join(cycle)}: each of these blocks needs "
                     "the output of the one before it within the same step; break the loop with a UnitDelay")
            found += 1
        return found

    def topological_order(self) -> list[str]:
        """The blocks without memory, each after those it reads; among the
        ready ones, the first in the model (so a model already in order
        keeps it)."""
        succ = self.edges()
        nodes = [b for b in self.blocks if not b.is_state]
        indeg = {b.name: 0 for b in nodes}
        for s, outs in succ.items():
            for t in outs:
                indeg[t] += 1
        ready = [(b.index, b.name) for b in nodes if indeg[b.name] == 0]
        heapq.heapify(ready)
        index = {b.name: b.index for b in nodes}
        order = []
        while ready:
            _, n = heapq.heappop(ready)
            order.append(n)
            for t in succ.get(n, ()):
                indeg[t] -= 1
                if indeg[t] == 0:
                    heapq.heappush(ready, (index[t], t))
        assert len(order) == len(nodes), "topological_order: a loop was not reported"
        return order

    # -- outports ------------------------------------------------------------------

    def outports_structure(self, onode) -> YMap | None:
        if onode is None or isinstance(onode, YBad):
            return None
        if not isinstance(onode, YMap):
            self.err(onode, f"controller.outports must be a mapping (output field: signal), got "
                     f"{onode.describe()}")
            return None
        return onode

    def outports(self, onode) -> list[tuple[ControllerField, str]] | None:
        m = self.outports_structure(onode)
        if m is None:
            return None
        taken: dict[str, str] = {}
        for k, v in m.items:
            name = k.text
            if name not in self.outputs:
                hint = (f" ({show(name)} is a controller input)" if name in self.inputs
                        else did_you_mean(name, list(self.outputs)))
                self.err(k, f"controller.outports: {show(name)} is not a controller output{hint}; the "
                         f"outputs are {_list(self.outputs)}")
                continue
            s = self.ck.string(v, f"controller.outports.{name}") if not isinstance(v, YBad) else None
            if s is None:
                continue
            if s not in self.by_name and s not in self.inputs:
                if s not in self.bad_names:
                    hint = did_you_mean(s, list(self.inputs) + list(self.by_name))
                    self.err(v, f"controller.outports.{name}: unknown signal {show(s)}{hint}")
                continue
            t, want = self.input_type(s), self.outputs[name][1].prim
            if t is not None and want in SIGNAL_TYPES and t != want and s not in self.tainted:
                self.err(v, f"controller.outports.{name}: type mismatch: output {show(name)} is {want} but "
                         f"signal {show(s)} is {t}")
                continue
            taken[name] = s
        for name in self.outputs:
            if m.get(name) is None:
                self.err(m.owner_pos, f"controller.outports: output {show(name)} takes no signal; every "
                         "controller output takes exactly one")
        if len(taken) != len(self.outputs):
            return None
        return [(f, taken[f.name]) for _, f in self.yfields]

    def used_inports(self, outports) -> set[str]:
        used = {s for b in self.blocks for s, _ in b.refs if s in self.inputs}
        if outports:
            used |= {s for _, s in outports if s in self.inputs}
        return used

    def c_temporaries(self, used: set[str]) -> None:
        """``rtb_<signal>`` of every equation: at most 63 characters and
        none of the names the controller's C defines."""
        globals_ = {}
        if self.uvar is not None:
            globals_[self.uvar] = "controller.inputs.name"
        if self.yvar is not None:
            globals_[self.yvar] = "controller.outputs.name"
        if self.ctrl_name is not None:
            for n in (f"{self.ctrl_name}_DW", f"{self.ctrl_name}_initialize", f"{self.ctrl_name}_step"):
                globals_[n] = f"controller {show(self.ctrl_name)}"
        for name in sorted(used, key=lambda n: list(self.inputs).index(n)):
            knode, _ = self.inputs[name]
            tmp = f"rtb_{name}"
            if len(tmp) > MAX_NAME_LEN:
                self.err(knode, f"controller input {show(name)} is read by the diagram: its C temporary "
                         f"{show(tmp)} would be longer than {MAX_NAME_LEN} characters; use a shorter name")
            elif tmp in globals_:
                self.err(knode, f"the C temporary {show(tmp)} of controller input {show(name)} collides with "
                         f"the name derived from {globals_[tmp]}")
        for b in self.blocks:
            if b.name is not None and f"rtb_{b.name}" in globals_:
                self.err(b.name_node, f"{b.what}: its C temporary {show('rtb_' + b.name)} collides with the "
                         f"name derived from {globals_['rtb_' + b.name]}")

    # -- the result ----------------------------------------------------------------

    def final(self, b: _B) -> Block:
        v = self.values.get(b.index, {})
        # what a valid block has (an internal check: a front-end bug must
        # not produce a diagram Coq would refuse without saying why)
        needs = {"Constant": ("value",), "Gain": ("gain",), "Saturation": ("lower", "upper"),
                 "UnitDelay": ("initial",), "DiscreteIntegrator": ("kt", "initial")}.get(b.kind, ())
        if (b.prim not in SIGNAL_TYPES or any(k not in v for k in needs)
                or (b.kind in ("RelationalOperator", "Switch") and b.input_prim is None)
                or (b.kind == "Switch" and b.op != "u2 ~= 0" and "threshold" not in v)):
            raise AssertionError(f"blocks: block {b.name!r} accepted incomplete")
        return Block(
            name=b.name,
            kind=b.kind,
            prim=b.prim,
            inputs=tuple(s for s, _ in b.refs),
            op=b.op,
            signs=b.signs,
            value=v.get("value"),
            gain=v.get("gain"),
            lower=v.get("lower"),
            upper=v.get("upper"),
            threshold=v.get("threshold"),
            initial=v.get("initial"),
            kt=v.get("kt"),
            input_prim=b.input_prim,
            pos=Pos(b.node.line, b.node.col),
        )


# --------------------------------------------------------------------------
# Values


def _num(s: Scalar):
    """A constant as a number of its type, for comparisons (floats as
    exact rationals: -0 equals +0)."""
    if s.prim in FLOAT_TYPES:
        return ieee.to_fraction(ieee.fmt(s.prim), s.n)
    return s.n


def zero(prim: str) -> Scalar:
    """The zero of a type (``Diagram.zero_of_prim``): ``+0.0`` for floats."""
    return Scalar(prim, 0, "false" if prim == "bool" else "0")


def scalar_of_text(text: str, prim: str) -> Scalar:
    """A constant from a decimal text known to be valid for ``prim``."""
    if prim in FLOAT_TYPES:
        return Scalar(prim, ieee.decimal_bits(text, ieee.fmt(prim)), text)
    if prim == "bool":
        return Scalar(prim, 1 if text.lower() == "true" else 0, text)
    return Scalar(prim, int(text), text)


def scalar_of(node: YNode, prim: str) -> tuple[Scalar | None, str | None]:
    """The constant of type ``prim`` written at ``node``, or why it is
    not one."""
    if prim == "bool":
        if isinstance(node, YScalar) and node.kind == "bool" and node.text.lower() in ("true", "false"):
            return Scalar(prim, 1 if node.value else 0, node.text), None
        return None, f"a bool constant is true or false, got {node.describe()}"
    if not (isinstance(node, YScalar) and node.kind in ("int", "float")):
        hint = ""
        if isinstance(node, YScalar) and node.kind == "str" and _NUMBER_LIKE.fullmatch(node.value):
            hint = (" (YAML 1.1 reads a number with an exponent as text unless it has a dot and a signed "
                    "exponent: write 1.0e-3 or 1.0e+5)")
        return None, f"expected a number of type {prim}, got {node.describe()}{hint}"
    if prim in INT_RANGES:
        if node.kind != "int":
            return None, f"{show(node.text)} is not an integer, and the type is {prim}"
        lo, hi = INT_RANGES[prim]
        if not lo <= node.value <= hi:
            return None, f"{node.text} is out of the range of {prim} ({lo} to {hi})"
        return Scalar(prim, node.value, node.text), None
    try:
        return Scalar(prim, ieee.decimal_bits(node.text, ieee.fmt(prim)), node.text), None
    except ieee.DecimalError as exc:
        return None, f"{show(node.text)} {exc}"


# --------------------------------------------------------------------------
# Graphs


def _sccs(nodes: list[str], succ: dict[str, list[str]]) -> list[list[str]]:
    """Tarjan's strongly connected components, without recursion."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    on_stack: set[str] = set()
    stack: list[str] = []
    comps: list[list[str]] = []
    counter = 0
    for root in nodes:
        if root in index:
            continue
        work = [(root, 0)]
        while work:
            v, i = work.pop()
            if i == 0:
                index[v] = low[v] = counter
                counter += 1
                stack.append(v)
                on_stack.add(v)
            outs = succ.get(v, [])
            recurse = False
            while i < len(outs):
                w = outs[i]
                i += 1
                if w not in index:
                    work.append((v, i))
                    work.append((w, 0))
                    recurse = True
                    break
                if w in on_stack:
                    low[v] = min(low[v], index[w])
            if recurse:
                continue
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on_stack.discard(w)
                    comp.append(w)
                    if w == v:
                        break
                comps.append(comp)
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[v])
    return comps


def _cycle_from(start: str, succ: dict[str, list[str]], within: set[str]) -> list[str]:
    """A shortest cycle through ``start`` inside ``within``, as
    ``[start, ..., start]`` (breadth-first from ``start``)."""
    prev: dict[str, str] = {}
    queue = deque([start])
    seen = {start}
    while queue:
        v = queue.popleft()
        for w in succ.get(v, ()):
            if w == start:
                path = [v]
                while path[-1] != start:
                    path.append(prev[path[-1]])
                return path[::-1] + [start]
            if w in within and w not in seen:
                seen.add(w)
                prev[w] = v
                queue.append(w)
    raise AssertionError("_cycle_from: start is on no cycle")  # pragma: no cover


def check_diagram(ck, cm: YMap | None, ctrl_name, ufields, yfields, uvar, yvar, period) -> Diagram | None:
    """Check ``controller.blocks`` and ``controller.outports`` (rule 4.11)
    and return the diagram, or ``None`` (no diagram, or problems, all
    reported through ``ck``)."""
    if cm is None:
        return None
    return _DiagramChecker(ck, cm, ctrl_name, ufields, yfields, uvar, yvar, period).run()
