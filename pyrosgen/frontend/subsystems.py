"""Rule 4.11: reusable subsystems of a block diagram, expanded away.

``controller.subsystems`` defines named subsystems, each a small diagram
with ordered ``inputs``, its own ``blocks`` and named ``outputs``; a block
of kind ``Subsystem`` instantiates one::

    subsystems:
      median3:
        inputs: [a, b, c]
        blocks:
          - {name: lo_ab, block: MinMax, function: min, inputs: [a, b]}
          ...
        outputs: {m: med}
    blocks:
      - {name: median, block: Subsystem, subsystem: median3, inputs: [In1, In2, In3]}
      - {name: err, block: Sum, inputs: [setpoint, median.m], signs: "+-"}

This module is a pure front-end expansion (:func:`expand`): before the
diagram is checked, every instance ``I`` is replaced, where it stands in the
list, by copies of its subsystem's blocks named ``I_<block>`` (nested
instances recursively: ``I_J_<block>``), their reads of the subsystem's
inputs replaced by the instance's input signals, and every read of an
instance's outport (``I.o``, or ``I`` alone when its subsystem has exactly
one outport) replaced by the signal inside that the outport names.  The
checker of :mod:`pyrosgen.frontend.blocks` then sees ordinary blocks only
(so do the types, the order, the emitted Coq and the proofs); each copy
keeps the position of the block it copies, so its problems are reported
where they were written.

Checked here, each at its place (rule 4.11): the shape of every definition
and instance; every signal a subsystem reads is one of its inputs or its
blocks (or an outport of an instance inside it); every input of a
subsystem is read; every subsystem has outputs and is instantiated; an
instance names a known subsystem and gives one signal per input; an
outport read exists; no subsystem contains itself, directly or not; every
expanded name is a usable block name that clashes with no other signal or
instance; the expanded diagram has at most ``limit`` blocks.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Callable

from pyrosgen.errors import show
from pyrosgen.frontend.names import did_you_mean, identifier_problem
from pyrosgen.frontend.yamlsrc import YBad, YMap, YNode, YScalar, YSeq

__all__ = ["Item", "Expansion", "expand", "SUBSYSTEM", "SEP"]

#: The block kind that instantiates a subsystem.
SUBSYSTEM = "Subsystem"

#: Between an instance's name and the name of one of its blocks.
SEP = "_"

#: At most this many levels of subsystems within subsystems.
MAX_NESTING = 16

#: The keys of a subsystem's definition, and of a Subsystem block.
DEF_KEYS = ("inputs", "blocks", "outputs")
INSTANCE_KEYS = ("name", "block", "subsystem", "inputs")

#: A signal as a subsystem sees it: ``("in", a)`` its input ``a``;
#: ``("block", b)`` its block ``b``; ``("port", i, o)`` outport ``o`` of its
#: instance ``i``; ``("outer", s)`` (top level only) a signal the checker
#: resolves (a block or a controller input).
Ref = tuple


def _is_str(node: YNode | None) -> bool:
    return isinstance(node, YScalar) and node.kind == "str"


def _str(at: YNode, value: str) -> YScalar:
    """A string scalar ``value`` at the position of ``at``."""
    return YScalar(at.line, at.col, value, value, "str")


def _list(names) -> str:
    return ", ".join(names)


@dataclass(frozen=True)
class Item:
    """A block of the expanded diagram, as the checker reads it: its
    mapping (name and input signals rewritten), where it was written
    (``controller.blocks[3]``, ``controller.subsystems.median3.blocks[0]``)
    and whether its shape problems were already reported with an earlier
    copy of the same block (``quiet``)."""

    node: YNode
    where: str
    quiet: bool = False


@dataclass(frozen=True)
class Expansion:
    """The expanded ``controller.blocks`` and ``controller.outports``."""

    items: tuple[Item, ...]
    outports: YNode | None


@dataclass
class _Inst:
    """A Subsystem block, as far as it could be checked."""

    node: YMap
    where: str                     # "controller.blocks[5] (median)"
    name: str | None = None
    name_node: YNode | None = None
    sub: str | None = None         # the subsystem it names (known once linked)
    sub_node: YNode | None = None
    refs: list[YScalar] = field(default_factory=list)   # its input signals
    refs_node: YNode | None = None
    broken: bool = False


@dataclass
class _Scope:
    """The blocks of the top level or of one subsystem."""

    what: str                      # "controller.blocks" or "controller.subsystems.S.blocks"
    owner: str | None              # the subsystem's name; None at the top level
    entries: list = field(default_factory=list)   # ("plain", YMap, name | None) | ("inst", _Inst) | ("raw", YNode)
    inputs: dict[str, YNode] = field(default_factory=dict)
    plain: dict[str, tuple[YNode, str]] = field(default_factory=dict)   # name -> (name node, where)
    insts: dict[str, _Inst] = field(default_factory=dict)
    refs: dict[int, Ref | None] = field(default_factory=dict)           # id(ref node) -> its signal
    broken: bool = False


@dataclass
class _Def:
    """A subsystem's definition."""

    name: str
    key: YScalar
    node: YMap
    scope: _Scope
    inputs: list[tuple[str, YNode]] = field(default_factory=list)
    outputs: dict[str, tuple[YScalar, YNode]] = field(default_factory=dict)   # outport -> (key, signal node)
    out_refs: dict[str, Ref | None] = field(default_factory=dict)
    inputs_ok: bool = True         # its inputs were read without a problem
    blocks_ok: bool = True         # its blocks are a list of blocks
    used: bool = False
    ok: bool | None = None         # expandable (computed)
    size: int | None = None        # its number of blocks, expanded


class _Frame:
    """One scope being expanded: the top level, or one instance of a
    subsystem (its name prefix and where its inputs come from)."""

    def __init__(self, ex: "_Expander", scope: _Scope, prefix: str, parent: "_Frame | None",
                 inst: _Inst | None, d: _Def | None):
        self.ex, self.scope, self.prefix, self.parent, self.inst, self.d = ex, scope, prefix, parent, inst, d
        self.children: dict[str, _Frame] = {}
        self.memo: dict[tuple[str, str], tuple[str, YNode]] = {}

    def child(self, name: str) -> "_Frame":
        if name not in self.children:
            inst = self.scope.insts[name]
            d = self.ex.defs[inst.sub]
            self.children[name] = _Frame(self.ex, d.scope, self.prefix + name + SEP, self, inst, d)
        return self.children[name]

    def signal(self, ref: Ref, node: YNode) -> tuple[str, YNode]:
        """The expanded signal of ``ref`` read at ``node``, and the node
        where that signal is written (for messages)."""
        kind = ref[0]
        if kind == "block":
            return self.prefix + ref[1], node
        if kind == "outer":
            return ref[1], node
        if kind == "port":
            return self.child(ref[1]).output(ref[2])[0], node
        return self.input(ref[1])

    def _memo(self, key: tuple[str, str], compute: Callable[[], tuple[str, YNode]]) -> tuple[str, YNode]:
        # no loop: an outport takes a block's signal, never an input's
        # (so each call goes one subsystem level down or up)
        if key not in self.memo:
            self.memo[key] = compute()
        return self.memo[key]

    def input(self, a: str) -> tuple[str, YNode]:
        """The signal the instance gives to its subsystem's input ``a``."""
        def compute():
            k = [n for n, _ in self.d.inputs].index(a)
            node = self.inst.refs[k]
            ref = self.parent.scope.refs.get(id(node))
            if ref is None:       # a top-level read left to the checker (its problem is reported)
                return node.value, node
            return self.parent.signal(ref, node)
        return self._memo(("in", a), compute)

    def output(self, o: str) -> tuple[str, YNode]:
        """The expanded signal of this instance's outport ``o``."""
        def compute():
            _, vnode = self.d.outputs[o]
            return self.signal(self.d.out_refs[o], vnode)
        return self._memo(("out", o), compute)

    def ref_node(self, node: YNode) -> YNode:
        """``node`` (a signal read), rewritten to the expanded signal."""
        ref = self.scope.refs.get(id(node))
        if ref is None:
            return node
        s, where = self.signal(ref, node)
        if where is node and s == node.value:
            return node
        return _str(where, s)

    def rewrite(self, node: YMap) -> YMap:
        """A copy of a plain block with its name prefixed and its reads
        rewritten."""
        items = []
        changed = False
        for k, v in node.items:
            w = v
            if k.text == "name" and _is_str(v) and self.prefix:
                w = _str(v, self.prefix + v.value)
            elif k.text == "input" and _is_str(v):
                w = self.ref_node(v)
            elif k.text == "inputs" and isinstance(v, YSeq):
                new = tuple(self.ref_node(x) if _is_str(x) else x for x in v.items)
                if any(a is not b for a, b in zip(new, v.items)):
                    w = YSeq(v.line, v.col, new)
            changed = changed or w is not v
            items.append((k, w))
        return YMap(node.line, node.col, tuple(items), node.owner) if changed else node

    def items(self) -> list[tuple[Item, str | None, int]]:
        """The expanded blocks of this scope, in order, each with its
        block's name before expansion and the identity of the block it
        copies."""
        out: list[tuple[Item, str | None, int]] = []
        for k, entry in enumerate(self.scope.entries):
            where = f"{self.scope.what}[{k}]"
            if entry[0] == "plain":
                node = entry[1]
                out.append((Item(self.rewrite(node), where), entry[2], id(node)))
            elif entry[0] == "inst":
                out.extend(self.child(entry[1].name).items())
            else:
                out.append((Item(entry[1], where), None, id(entry[1])))
        return out


class _Expander:
    def __init__(self, err: Callable[[object, str], None], string: Callable[[YNode, str], str | None],
                 cm: YMap, bnode: YSeq, onode: YNode | None, inputs: dict[str, YNode],
                 bad_names: set[str], limit: int, max_name: int):
        self.err, self.string = err, string
        self.cm, self.bnode, self.onode = cm, bnode, onode
        self.controller_inputs = inputs
        self.bad_names = bad_names
        self.limit, self.max_name = limit, max_name
        self.defs: dict[str, _Def] = {}
        self.errors = 0
        self.emitted: set[int] = set()
        self.post: list[_Def] = []     # the subsystems, each after those it uses

    def report(self, where, message: str) -> None:
        self.errors += 1
        self.err(where, message)

    # -- reading ---------------------------------------------------------------

    def parse_defs(self, snode: YNode) -> None:
        if isinstance(snode, YBad):
            return
        if not isinstance(snode, YMap):
            self.report(snode, f"controller.subsystems must be a mapping (subsystem name: definition), got "
                        f"{snode.describe()}")
            return
        for key, value in snode.items:
            name = key.text
            what = f"controller.subsystems.{name}"
            problem = identifier_problem(name, global_scope=True)
            if problem:
                self.report(key, f"controller.subsystems: subsystem name {show(name)} cannot be used: {problem}")
                continue
            if isinstance(value, YBad):
                continue
            if not isinstance(value, YMap):
                self.report(value, f"{what} must be a mapping (inputs: [...], blocks: [...], outputs: {{...}}), "
                            f"got {value.describe()}")
                continue
            d = _Def(name, key, value, _Scope(f"{what}.blocks", name))
            self.defs[name] = d
            for k in value.keys():
                if k not in DEF_KEYS:
                    self.report(value.key_node(k), f"{what}: a subsystem has no key {show(k)}"
                                f"{did_you_mean(k, DEF_KEYS)}; its keys are {_list(DEF_KEYS)}")
            self.parse_inputs(d)
            blocks = value.get("blocks")
            if blocks is None:
                self.report(value.owner_pos, f"{what}: missing key 'blocks' (the subsystem's blocks)")
                d.scope.broken = True
                d.blocks_ok = False
            elif isinstance(blocks, YBad):
                d.scope.broken = True
                d.blocks_ok = False
            elif not isinstance(blocks, YSeq):
                self.report(blocks, f"{what}.blocks must be a list of blocks, got {blocks.describe()}")
                d.scope.broken = True
                d.blocks_ok = False
            elif not blocks.items:
                self.report(blocks, f"{what}.blocks must list at least one block")
                d.scope.broken = True
                d.blocks_ok = False
            else:
                self.parse_scope(d.scope, blocks.items)
            self.parse_outputs(d)

    def parse_inputs(self, d: _Def) -> None:
        what = f"controller.subsystems.{d.name}.inputs"
        node = d.node.get("inputs")
        if node is None:
            return          # no inputs
        if isinstance(node, YBad):
            d.scope.broken = d.inputs_ok = False
            return
        if not isinstance(node, YSeq):
            self.report(node, f"{what} must be a list of input names, got {node.describe()}")
            d.scope.broken = d.inputs_ok = False
            return
        for k, item in enumerate(node.items):
            s = self.string(item, f"{what}[{k}]") if not isinstance(item, YBad) else None
            if s is None:
                d.scope.broken = d.inputs_ok = False
                continue
            problem = identifier_problem(s, global_scope=True)
            if problem:
                self.report(item, f"{what}[{k}]: input name {show(s)} cannot be used: {problem}")
                d.scope.broken = d.inputs_ok = False
            elif s in d.scope.inputs:
                self.report(item, f"{what}[{k}]: input {show(s)} is listed twice (first at line "
                            f"{d.scope.inputs[s].line})")
                d.scope.broken = d.inputs_ok = False
            else:
                d.scope.inputs[s] = item
                d.inputs.append((s, item))

    def parse_outputs(self, d: _Def) -> None:
        what = f"controller.subsystems.{d.name}"
        node = d.node.get("outputs")
        if node is None or (isinstance(node, YMap) and not node.items):
            where = d.node.owner_pos if node is None else node
            self.report(where, f"{what}: a subsystem has at least one output (outputs: {{<outport>: <signal>}}); "
                        "its outports are what an instance gives to the diagram")
            d.scope.broken = True
            return
        if isinstance(node, YBad):
            d.scope.broken = True
            return
        if not isinstance(node, YMap):
            self.report(node, f"{what}.outputs must be a mapping (outport name: signal), got {node.describe()}")
            d.scope.broken = True
            return
        for key, value in node.items:
            problem = identifier_problem(key.text, global_scope=True)
            if problem:
                self.report(key, f"{what}.outputs: outport name {show(key.text)} cannot be used: {problem}")
                d.scope.broken = True
                continue
            if isinstance(value, YBad) or self.string(value, f"{what}.outputs.{key.text}") is None:
                d.scope.broken = True
                continue
            d.outputs[key.text] = (key, value)

    def parse_scope(self, scope: _Scope, items) -> None:
        """The entries of a list of blocks, and the names they define."""
        top = scope.owner is None
        for k, item in enumerate(items):
            where = f"{scope.what}[{k}]"
            if not isinstance(item, YMap):
                scope.entries.append(("raw", item))
                if not top and not isinstance(item, YBad):
                    self.report(item, f"{where} must be a mapping (name: ..., block: ..., ...), got "
                                f"{item.describe()}")
                if not top:
                    scope.broken = True
                continue
            knode = item.get("block")
            if _is_str(knode) and knode.value == SUBSYSTEM:
                scope.entries.append(("inst", self.parse_instance(scope, item, where)))
                continue
            nnode = item.get("name")
            name = nnode.value if _is_str(nnode) and nnode.value else None
            scope.entries.append(("plain", item, name))
            if name is None:
                continue       # the checker reports a missing or bad name
            if top:
                # the checker reports bad names and a name driven twice
                # by blocks; here, a block named like a Subsystem block
                if name in scope.insts:
                    self.clash(scope, name, nnode, f"{where} ({name})")
                scope.plain.setdefault(name, (nnode, f"{where} ({name})"))
                continue
            problem = identifier_problem(name, global_scope=True)
            if problem:
                self.report(nnode, f"{where}.name: block name {show(name)} cannot be used: {problem}")
                scope.broken = True
            elif self.clash(scope, name, nnode, f"{where} ({name})"):
                scope.broken = True
            else:
                scope.plain[name] = (nnode, f"{where} ({name})")

    def clash(self, scope: _Scope, name: str, node: YNode, what: str) -> bool:
        """Whether ``name`` is already a signal or an instance of ``scope``
        (reported)."""
        first = None
        if name in scope.inputs:
            first = f"input {show(name)} of subsystem {show(scope.owner)} (line {scope.inputs[name].line})"
        elif name in scope.plain:
            n, w = scope.plain[name]
            first = f"{w} (line {n.line})"
        elif name in scope.insts:
            i = scope.insts[name]
            first = f"the Subsystem block {i.where} (line {i.name_node.line})"
        if first is None:
            return False
        self.report(node, f"{what}: signal {show(name)} is driven twice: by this block and by {first}")
        return True

    def parse_instance(self, scope: _Scope, item: YMap, where: str) -> _Inst:
        inst = _Inst(item, where)
        nnode = item.get("name")
        inst.name_node = nnode if nnode is not None else item
        if nnode is None:
            self.report(item.owner_pos, f"{where}: missing key 'name' (the instance's name; its outports are "
                        "read as <name>.<outport>)")
            inst.broken = True
        else:
            name = self.string(nnode, f"{where}.name")
            problem = identifier_problem(name, global_scope=True) if name is not None else None
            if name is None:
                inst.broken = True
            elif problem:
                self.report(nnode, f"{where}.name: instance name {show(name)} cannot be used: {problem}")
                self.bad_names.add(name)
                inst.broken = True
            else:
                inst.where = f"{where} ({name})"
                if scope.owner is None and name in self.controller_inputs:
                    knode = self.controller_inputs[name]
                    self.report(nnode, f"{inst.where}: signal {show(name)} is driven twice: by this block and "
                                f"by controller input {show(name)} (line {knode.line})")
                    inst.broken = True
                elif self.clash(scope, name, nnode, inst.where):
                    inst.broken = True
                else:
                    inst.name = name
                    scope.insts[name] = inst
                if inst.broken:
                    self.bad_names.add(name)
        for k in item.keys():
            if k not in INSTANCE_KEYS:
                self.report(item.key_node(k), f"{inst.where}: a Subsystem block has no key {show(k)}"
                            f"{did_you_mean(k, INSTANCE_KEYS)}; its keys are {_list(INSTANCE_KEYS)}")
        snode = item.get("subsystem")
        if snode is None:
            self.report(item.owner_pos, f"{inst.where}: missing key 'subsystem' (the name of the subsystem "
                        "it instantiates, from controller.subsystems)")
            inst.broken = True
        else:
            inst.sub_node = snode
            inst.sub = self.string(snode, f"{inst.where}.subsystem")
            inst.broken = inst.broken or inst.sub is None
        rnode = item.get("inputs")
        inst.refs_node = rnode
        if rnode is not None:
            if isinstance(rnode, YBad):
                inst.broken = True
            elif not isinstance(rnode, YSeq):
                self.report(rnode, f"{inst.where}.inputs must be a list of signal names, got {rnode.describe()}")
                inst.broken = True
            else:
                for k, x in enumerate(rnode.items):
                    if isinstance(x, YBad) or self.string(x, f"{inst.where}.inputs[{k}]") is None:
                        inst.broken = True
                    else:
                        inst.refs.append(x)
        if scope.owner is not None and inst.broken:
            scope.broken = True
        return inst

    # -- linking -----------------------------------------------------------------

    def scopes(self) -> list[_Scope]:
        return [d.scope for d in self.defs.values()] + [self.top]

    def link(self) -> None:
        """Every instance names a known subsystem and gives it one signal
        per input."""
        for scope in self.scopes():
            for entry in scope.entries:
                if entry[0] != "inst" or entry[1].sub is None:
                    continue
                inst = entry[1]
                d = self.defs.get(inst.sub)
                if d is None:
                    hint = did_you_mean(inst.sub, list(self.defs))
                    known = (f"; the subsystems are {_list(self.defs)}" if self.defs
                             else "; define it under controller.subsystems")
                    self.report(inst.sub_node, f"{inst.where}: unknown subsystem {show(inst.sub)}{hint}{known}")
                    inst.sub = None
                    self.broken(scope, inst)
                    continue
                d.used = True
                refs_ok = inst.refs_node is None or (isinstance(inst.refs_node, YSeq)
                                                     and len(inst.refs) == len(inst.refs_node.items))
                if not (refs_ok and d.inputs_ok):
                    continue
                if len(inst.refs) != len(d.inputs):
                    where = inst.refs_node if inst.refs_node is not None else inst.node.owner_pos
                    self.report(where, f"{inst.where}: subsystem {show(d.name)} takes {len(d.inputs)} "
                                f"input{'s' if len(d.inputs) != 1 else ''} [{_list(n for n, _ in d.inputs)}], "
                                f"got {len(inst.refs)}")
                    self.broken(scope, inst)
        for d in self.defs.values():
            if not d.used:
                self.report(d.key, f"controller.subsystems.{d.name}: subsystem {show(d.name)} is instantiated "
                            f"by no block; remove it, or use it (block: {SUBSYSTEM}, subsystem: {d.name})")

    def broken(self, scope: _Scope, inst: _Inst) -> None:
        inst.broken = True
        if inst.name is not None:
            self.bad_names.add(inst.name)
        if scope.owner is not None:
            scope.broken = True

    def recursion(self) -> None:
        """No subsystem contains itself, directly or not."""
        uses: dict[str, list[_Inst]] = {
            d.name: [e[1] for e in d.scope.entries if e[0] == "inst" and e[1].sub in self.defs]
            for d in self.defs.values()}
        state: dict[str, int] = {}       # 1: on the path, 2: done
        reported: set[str] = set()
        for root in self.defs:
            if root in state:
                continue
            path: list[tuple[str, _Inst | None]] = [(root, None)]
            stack = [(root, iter(uses[root]))]
            state[root] = 1
            while stack:
                name, it = stack[-1]
                inst = next(it, None)
                if inst is None:
                    state[name] = 2
                    self.post.append(self.defs[name])
                    stack.pop()
                    path.pop()
                    continue
                t = inst.sub
                if state.get(t) == 1:
                    names = [n for n, _ in path]
                    cycle = names[names.index(t):] + [t]
                    for n in cycle:
                        self.defs[n].scope.broken = True
                    if not reported & set(cycle):
                        self.report(inst.sub_node, f"{inst.where}: subsystem {show(t)} contains itself: "
                                    f"{' -> '.join(cycle)}; a subsystem cannot instantiate itself, directly or "
                                    "through others")
                    reported |= set(cycle)
                    inst.broken = True
                elif t not in state:
                    state[t] = 1
                    path.append((t, inst))
                    stack.append((t, iter(uses[t])))

    # -- signals -----------------------------------------------------------------

    def resolve(self, scope: _Scope, s: str, node: YNode, what: str) -> Ref | None:
        """The signal ``s`` read at ``node`` in ``scope``, or ``None``
        (reported, or a consequence of a problem already reported)."""
        inner = scope.owner is not None
        if "." in s:
            i, _, o = s.partition(".")
            inst = scope.insts.get(i)
            if inst is None:
                if i in self.bad_names and not inner:
                    self.bad_names.add(s)
                    return None
                where = f" in subsystem {show(scope.owner)}" if inner else ""
                self.report(node, f"{what}: unknown signal {show(s)}: {show(i)} is not a Subsystem block{where} "
                            f"(<instance>.<outport> reads an outport of a Subsystem block)"
                            f"{did_you_mean(i, list(scope.insts))}")
                return self.fail(scope, s)
            if inst.broken or inst.sub is None or self.defs[inst.sub].scope.broken:
                return self.fail(scope, s)
            d = self.defs[inst.sub]
            if o not in d.outputs:
                self.report(node, f"{what}: {show(s)}: subsystem {show(d.name)} of {show(i)} has no outport "
                            f"{show(o)}{did_you_mean(o, list(d.outputs))}; its outports are {_list(d.outputs)}")
                return self.fail(scope, s)
            return ("port", i, o)
        if s in scope.inputs:
            return ("in", s)
        if s in scope.plain:
            return ("block", s)
        if s in scope.insts:
            inst = scope.insts[s]
            if inst.broken or inst.sub is None or self.defs[inst.sub].scope.broken:
                return self.fail(scope, s)
            d = self.defs[inst.sub]
            if len(d.outputs) != 1:
                self.report(node, f"{what}: {show(s)} is a Subsystem block with {len(d.outputs)} outports "
                            f"({_list(d.outputs)}); read one of them as {s}.<outport>, e.g. "
                            f"{s}.{next(iter(d.outputs))}")
                return self.fail(scope, s)
            return ("port", s, next(iter(d.outputs)))
        if not inner:
            known = s in self.controller_inputs or s in scope.plain
            return ("outer", s) if known or s not in self.bad_names else None
        d = self.defs[scope.owner]
        if s in self.bad_names or not (d.inputs_ok and d.blocks_ok):
            scope.broken = True       # reported already (a bad name, the subsystem's inputs)
            return None
        hint = did_you_mean(s, list(scope.inputs) + list(scope.plain) + list(scope.insts))
        if not hint and s in self.controller_inputs:
            hint = (f" (controller input {show(s)} is not seen inside a subsystem: add an input to the "
                    "subsystem and give it the signal in each Subsystem block)")
        self.report(node, f"{what}: unknown signal {show(s)} in subsystem {show(scope.owner)}; a subsystem "
                    f"reads its inputs ({_list(scope.inputs) or 'none'}) and its own blocks{hint}")
        return self.fail(scope, s)

    def fail(self, scope: _Scope, s: str) -> None:
        """A read that cannot be expanded: the top level's is left to the
        checker, which does not report it again; a subsystem's breaks it."""
        if scope.owner is None:
            self.bad_names.add(s)
        else:
            scope.broken = True
        return None

    def reads(self, scope: _Scope) -> list[tuple[YScalar, str]]:
        """The signal reads of a scope's blocks and instances, each with
        what reads it."""
        out = []
        for k, entry in enumerate(scope.entries):
            if entry[0] == "plain":
                node = entry[1]
                what = f"{scope.what}[{k}]" + (f" ({entry[2]})" if entry[2] else "")
                v = node.get("input")
                if _is_str(v):
                    out.append((v, what))
                v = node.get("inputs")
                if isinstance(v, YSeq):
                    out.extend((x, what) for x in v.items if _is_str(x))
            elif entry[0] == "inst":
                out.extend((x, entry[1].where) for x in entry[1].refs)
        return out

    def resolve_scope(self, scope: _Scope) -> None:
        for node, what in self.reads(scope):
            scope.refs[id(node)] = self.resolve(scope, node.value, node, what) if node.value else None

    def resolve_def(self, d: _Def) -> None:
        self.resolve_scope(d.scope)
        what = f"controller.subsystems.{d.name}.outputs"
        for o, (key, value) in d.outputs.items():
            ref = self.resolve(d.scope, value.value, value, f"{what}.{o}")
            if ref is not None and ref[0] == "in":
                self.report(value, f"{what}.{o}: outport {show(o)} passes input {show(ref[1])} on unchanged; "
                            "an outport takes the signal of one of the subsystem's blocks (where the outport "
                            "is read, read the instance's input signal instead)")
                d.scope.broken = True
                ref = None
            d.out_refs[o] = ref
        read = {r[1] for r in list(d.scope.refs.values()) + list(d.out_refs.values())
                if r is not None and r[0] == "in"}
        for name, node in d.inputs if d.blocks_ok else ():
            if name not in read:
                self.report(node, f"controller.subsystems.{d.name}.inputs: input {show(name)} is read by none "
                            "of the subsystem's blocks or outputs; remove it (and its signal from each "
                            f"{SUBSYSTEM} block)")

    def nesting(self) -> None:
        """Which subsystems can be expanded (``ok``), their sizes and
        depths, each computed after those of the subsystems it uses; a
        subsystem nested more than :data:`MAX_NESTING` deep is refused."""
        depth: dict[str, int] = {}
        for d in self.post:
            insts = [e[1] for e in d.scope.entries if e[0] == "inst"]
            inner = [self.defs[i.sub] for i in insts if i.sub in self.defs]
            depth[d.name] = 1 + max((depth.get(t.name, 0) for t in inner), default=0)
            if depth[d.name] == MAX_NESTING + 1:
                self.report(d.key, f"controller.subsystems.{d.name}: subsystem {show(d.name)} nests subsystems "
                            f"{MAX_NESTING + 1} deep; at most {MAX_NESTING} levels")
            d.ok = (depth[d.name] <= MAX_NESTING and not d.scope.broken
                    and all(not i.broken and i.sub in self.defs and self.defs[i.sub].ok for i in insts))
            d.size = sum(1 for e in d.scope.entries if e[0] != "inst") + sum(t.size or 0 for t in inner)

    def size(self, scope: _Scope) -> int:
        """The number of blocks of ``scope``, expanded."""
        return sum(1 if e[0] != "inst" else (self.defs[e[1].sub].size or 0) if e[1].sub in self.defs else 0
                   for e in scope.entries)

    # -- the whole -----------------------------------------------------------------

    def run(self) -> Expansion | None:
        snode = self.cm.get("subsystems")
        if snode is not None:
            self.parse_defs(snode)
        self.top = _Scope("controller.blocks", None)
        self.parse_scope(self.top, self.bnode.items)
        if snode is None and not any(e[0] == "inst" for e in self.top.entries):
            # no subsystem anywhere: the diagram is read as written
            # (dotted signals are then unknown signals, as before)
            return Expansion(tuple(Item(x, f"controller.blocks[{k}]") for k, x in enumerate(self.bnode.items)),
                             self.onode)
        self.link()
        self.recursion()
        for d in self.defs.values():
            self.resolve_def(d)
        self.nesting()
        for e in self.top.entries:
            if e[0] == "inst" and not e[1].broken and (e[1].sub is None or not self.defs[e[1].sub].ok):
                self.broken(self.top, e[1])
        self.resolve_scope(self.top)
        total = self.size(self.top)
        if total > self.limit:
            self.report(self.bnode, f"controller.blocks lists {total} blocks once its {SUBSYSTEM} blocks are "
                        f"expanded; a diagram has at most {self.limit}")
            return None
        frame = _Frame(self, self.top, "", None, None, None)
        items = self.expand_top(frame)
        return Expansion(tuple(items), self.rewrite_outports(frame))

    def expand_top(self, frame: _Frame) -> list[Item]:
        """The expanded top level: each instance's blocks checked for
        their names before they are kept."""
        taken: dict[str, str] = {}
        for name, node in self.controller_inputs.items():
            taken[name] = f"controller input {show(name)} (line {node.line})"
        for k, e in enumerate(self.top.entries):
            if e[0] == "plain" and e[2] is not None:
                taken.setdefault(e[2], f"controller.blocks[{k}] ({e[2]}) (line {e[1].line})")
            elif e[0] == "inst" and e[1].name is not None:
                taken.setdefault(e[1].name, f"the {SUBSYSTEM} block {e[1].where} (line {e[1].node.line})")
        out: list[Item] = []
        for k, e in enumerate(self.top.entries):
            if e[0] == "plain":
                out.append(Item(frame.rewrite(e[1]), f"controller.blocks[{k}]"))
            elif e[0] == "raw":
                out.append(Item(e[1], f"controller.blocks[{k}]"))
            elif not e[1].broken:
                inst = e[1]
                child = frame.child(inst.name)
                mine = child.items()
                if self.names_ok(inst, mine, taken):
                    for item, inner, src in mine:
                        nnode = item.node.get("name")
                        if _is_str(nnode):
                            taken[nnode.value] = (f"{item.where} ({inner}) in instance {show(inst.name)} "
                                                  f"(line {item.node.line})")
                        out.append(replace(item, quiet=src in self.emitted))
                        self.emitted.add(src)
                else:
                    self.bad_names.add(inst.name)
                    for o in self.defs[inst.sub].outputs:
                        self.bad_names.add(child.output(o)[0])
        return out

    def names_ok(self, inst: _Inst, mine: list[tuple[Item, str | None, int]], taken: dict[str, str]) -> bool:
        """Every expanded name of one top-level instance is a usable block
        name, new (reported at the instance's name)."""
        seen: dict[str, str] = {}
        for item, inner, _ in mine:
            nnode = item.node.get("name")
            if not _is_str(nnode):
                continue       # reported by the checker
            flat = nnode.value
            src = f"{item.where} ({inner}, line {item.node.line})"
            problem = identifier_problem(flat, global_scope=True)
            if problem is None and len(flat) > self.max_name:
                problem = (f"it is longer than {self.max_name} characters ({len(flat)}; its C temporary is "
                           "rtb_<name>); use a shorter instance name")
            if problem:
                self.report(inst.name_node, f"{inst.where}: the expansion of this {SUBSYSTEM} block names "
                            f"{src} {show(flat)}, which cannot be used: {problem}")
                return False
            first = taken.get(flat) or seen.get(flat)
            if first is not None:
                self.report(inst.name_node, f"{inst.where}: the expansion of this {SUBSYSTEM} block names "
                            f"{src} {show(flat)}, which is already the name of {first}; rename the instance "
                            "or one of the blocks")
                return False
            seen[flat] = f"{src} in the same instance"
        return True

    def rewrite_outports(self, frame: _Frame) -> YNode | None:
        m = self.onode
        if not isinstance(m, YMap):
            return m
        items = []
        for k, v in m.items:
            if _is_str(v) and v.value:
                ref = self.resolve(self.top, v.value, v, f"controller.outports.{k.text}")
                if ref is not None:
                    s, where = frame.signal(ref, v)
                    if s != v.value or where is not v:
                        v = _str(where, s)
            items.append((k, v))
        return YMap(m.line, m.col, tuple(items), m.owner)


def expand(err: Callable[[object, str], None], string: Callable[[YNode, str], str | None], cm: YMap,
           bnode: YSeq, onode: YNode | None, inputs: dict[str, YNode], bad_names: set[str], *,
           limit: int, max_name: int) -> Expansion | None:
    """Expand the Subsystem blocks of ``controller.blocks`` (and the reads
    of their outports in the blocks and ``controller.outports``), reporting
    every problem through ``err``; ``None`` when the diagram cannot be
    expanded at all.  ``inputs``: the controller inputs' names and nodes;
    ``bad_names``: the names whose reads the checker must not report as
    unknown signals (added to here); ``limit``: the most blocks a diagram
    has once expanded; ``max_name``: the longest block name."""
    return _Expander(err, string, cm, bnode, onode, inputs, bad_names, limit, max_name).run()
