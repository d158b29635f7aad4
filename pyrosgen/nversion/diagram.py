"""The diagram text of a block-diagram controller (rule 4.11), read a
second time from the YAML file (N-version, DESIGN.md section 7): the
format of ``coq/theories/ctrl/DiagramText.v``, the meaning of DESIGN.md
rule 4.11 (subsystems expanded, types inferred, constants read in their
type, the evaluation order), without the front end."""

from __future__ import annotations

import heapq
from fractions import Fraction
from pathlib import Path

from pyrosgen.nversion.msgs import ReadingError
from pyrosgen.nversion.reader import Line, Num, YDict, _ctrl_fields, _float_bits, _int, _line, read_yaml

__all__ = ["diagram_text", "diagram_lines", "has_diagram"]

HEADER = "pyrosgen-diagram 1"
STATES = ("UnitDelay", "DiscreteIntegrator")
RELOPS = {"==": "==", "~=": "!=", "!=": "!=", "<": "<", "<=": "<=", ">": ">", ">=": ">="}
CRITERIA = {"u2 >= threshold": ">=", "u2 > threshold": ">", "u2 ~= 0": "~=0"}


def has_diagram(path, *, doc=None) -> bool:
    """Whether the model file's controller is a block diagram."""
    if doc is None:
        doc = read_yaml(Path(path))
    return isinstance(doc, dict) and isinstance(doc.get("controller"), dict) and "blocks" in doc["controller"]


# --------------------------------------------------------------------------
# Subsystems: a front-end expansion (rule 4.11), done again


class _Scope:
    """The blocks of one diagram level: the top level, or one instance of
    a subsystem (``prefix`` ``I_``, ``I_J_``; ``inputs`` its inputs'
    signals, already resolved)."""

    def __init__(self, blocks, prefix: str, inputs: dict[str, str], subsystems: dict, depth: int):
        if depth > 32:
            raise ReadingError("subsystems nested too deep")
        self.prefix, self.inputs, self.subsystems = prefix, inputs, subsystems
        self.blocks = list(blocks)
        self.instances: dict[str, tuple[dict, _Scope | None]] = {}
        for b in self.blocks:
            if b.get("block") == "Subsystem":
                self.instances[b["name"]] = (subsystems[b["subsystem"]], None)
        self.depth = depth

    def instance(self, name: str) -> "_Scope":
        sdef, scope = self.instances[name]
        if scope is None:
            b = next(x for x in self.blocks if x.get("name") == name)
            args = [self.resolve(s) for s in (b.get("inputs") or [])]
            params = list(sdef.get("inputs") or [])
            if len(args) != len(params):
                raise ReadingError(f"instance {name}: {len(args)} inputs for {len(params)}")
            scope = _Scope(sdef["blocks"], f"{self.prefix}{name}_", dict(zip(params, args)), self.subsystems,
                           self.depth + 1)
            self.instances[name] = (sdef, scope)
        return scope

    def resolve(self, s: str) -> str:
        """The expanded signal that ``s`` names at this level."""
        if not isinstance(s, str):
            raise ReadingError(f"a signal is a name, got {s!r}")
        if s in self.inputs:
            return self.inputs[s]
        inst, dot, out = s.partition(".")
        if inst in self.instances:
            outs = self.instances[inst][0]["outputs"]
            if not dot:
                if len(outs) != 1:
                    raise ReadingError(f"{s}: subsystem instance with {len(outs)} outports read whole")
                out = next(iter(outs))
            scope = self.instance(inst)
            return scope.resolve(outs[out])
        if dot:
            raise ReadingError(f"unknown instance in {s!r}")
        return self.prefix + s

    def expand(self) -> list[dict]:
        out = []
        for b in self.blocks:
            if b.get("block") == "Subsystem":
                out += self.instance(b["name"]).expand()
                continue
            c = YDict(b)
            c.line, c.col = getattr(b, "line", None), getattr(b, "col", None)
            c["name"] = self.prefix + b["name"]
            if "input" in b:
                c["input"] = self.resolve(b["input"])
            if "inputs" in b:
                c["inputs"] = [self.resolve(s) for s in b["inputs"]]
            out.append(c)
        return out


# --------------------------------------------------------------------------
# Constants


def _val(x, prim: str, scale: Fraction | None = None) -> str:
    """A constant written ``x`` read in type ``prim``, as ``val_text``
    prints it (``scale``: a float multiplied exactly before rounding)."""
    if prim == "bool":
        if x is True or x is False:
            return "1" if x else "0"
        raise ReadingError(f"not a bool constant: {x!r}")
    if not isinstance(x, Num):
        raise ReadingError(f"not a number: {x!r}")
    if prim in ("float32", "float64"):
        return f"0x{_float_bits(x.text, prim, scale):0{16 if prim == 'float64' else 8}x}"
    return str(_int(x))


def _refs(b) -> list[str]:
    if "input" in b:
        return [b["input"]]
    return list(b.get("inputs") or [])


# --------------------------------------------------------------------------
# The text


def diagram_text(path, *, doc=None) -> str:
    """The canonical diagram text (the grammar of
    ``DiagramText.print_diagram``) of the model file at ``path``, read
    without the front end (``doc``: the file as ``read_yaml`` read it)."""
    return "".join(line + "\n" for line in diagram_lines(path, doc=doc))


def diagram_lines(path, *, doc=None) -> list[Line]:
    """The lines of :func:`diagram_text`, each with the place of the YAML
    file it comes from (a block's for its equation and state lines)."""
    if doc is None:
        doc = read_yaml(Path(path))
    ctrl = doc["controller"]
    period = _int(doc["node"]["period_ms"])
    name = ctrl["name"]
    inputs = _ctrl_fields(ctrl["inputs"]["fields"])
    outputs = _ctrl_fields(ctrl["outputs"]["fields"])
    if any(s is not None for _, _, s in inputs + outputs):
        raise ReadingError("a block diagram's inputs and outputs are scalars")
    in_type = {n: p for n, p, _ in inputs}

    top = _Scope(ctrl["blocks"], "", {}, dict(ctrl.get("subsystems") or {}), 0)
    blocks = top.expand()
    outports = [(f, top.resolve(ctrl["outports"][f])) for f, _, _ in outputs]
    by_name = {b["name"]: b for b in blocks}
    if len(by_name) != len(blocks):
        raise ReadingError("two blocks drive one signal")

    # types: from the constants, the declared delays, the comparisons and
    # the inputs, along the blocks (a well-typed diagram has one answer)
    prim: dict[str, str] = dict(in_type)
    changed = True
    while changed:
        changed = False
        for b in blocks:
            n = b["name"]
            if n in prim:
                continue
            kind = b["block"]
            t = None
            if kind == "Constant":
                t = b["type"]
            elif kind in ("RelationalOperator", "Logic"):
                t = "bool"
            elif kind == "UnitDelay" and "type" in b:
                t = b["type"]
            else:
                refs = _refs(b)
                if kind == "Switch":
                    refs = [refs[0], refs[2]]
                t = next((prim[s] for s in refs if s in prim), None)
            if t is not None:
                prim[n] = t
                changed = True
    missing = [b["name"] for b in blocks if b["name"] not in prim]
    if missing:
        raise ReadingError(f"the type of {missing[0]!r} cannot be inferred")

    def block_text(b) -> str:
        kind, refs, q = b["block"], _refs(b), prim[b["name"]]
        if kind == "Constant":
            return f"const {_val(b['value'], q)}"
        if kind == "Gain":
            return f"gain {_val(b['gain'], q)} {refs[0]}"
        if kind == "Sum":
            signs = b.get("signs", "+" * len(refs))
            if len(signs) != len(refs):
                raise ReadingError(f"block {b['name']}: {len(signs)} signs for {len(refs)} inputs")
            return "sum " + " ".join(sg + r for sg, r in zip(signs, refs))
        if kind in ("Product", "Divide"):
            return f"{kind.lower()} {refs[0]} {refs[1]}"
        if kind == "Abs":
            return f"abs {refs[0]}"
        if kind == "MinMax":
            return " ".join([b["function"], *refs])
        if kind == "Saturation":
            return f"saturation {_val(b['lower'], q)} {_val(b['upper'], q)} {refs[0]}"
        if kind == "RelationalOperator":
            return f"relational {RELOPS[b['operator']]} {prim[refs[0]]} {refs[0]} {refs[1]}"
        if kind == "Logic":
            return " ".join(["logic", b["operator"], *refs])
        if kind == "Switch":
            qc = prim[refs[1]]
            crit = CRITERIA[b["criterion"]]
            thr = "0" if crit == "~=0" else _val(b["threshold"], qc)
            return f"switch {crit} {qc} {thr} {refs[0]} {refs[1]} {refs[2]}"
        raise ReadingError(f"block {b['name']}: unknown kind {kind!r}")

    def zero(q: str) -> Num | bool:
        return False if q == "bool" else Num("0", 0)

    lines = [
        HEADER,
        f"controller {name}",
        f"inputs {ctrl['inputs']['name']} ExtU_{name}_T",
        *(f"input {n} {p}" for n, p, _ in inputs),
        f"outputs {ctrl['outputs']['name']} ExtY_{name}_T",
        *(f"output {n} {p}" for n, p, _ in outputs),
        f"states {name}_DW DW_{name}_T",
    ]
    states = [b for b in blocks if b["block"] in STATES]
    for st in states:
        q = prim[st["name"]]
        line = f"state {st['name']} {q} {_val(st.get('initial', zero(q)), q)} {_refs(st)[0]}"
        if st["block"] == "UnitDelay":
            line += " delay"
        else:
            kt = _val(st.get("gain", Num("1", 1)), q, Fraction(period, 1000))
            line += f" integrator {kt}"
            if "lower" in st:
                line += f" {_val(st['lower'], q)} {_val(st['upper'], q)}"
        lines.append(_line(line, st))
    used = {s for b in blocks for s in _refs(b)} | {s for _, s in outports}
    lines += [f"eq {n} {p} inport {n}" for n, p, _ in inputs if n in used]
    lines += [_line(f"eq {st['name']} {prim[st['name']]} state {st['name']}", st) for st in states]

    # the blocks without memory, each after those it reads within the
    # step; among the ready ones, the first in the (expanded) model
    index = {b["name"]: i for i, b in enumerate(blocks)}
    plain = [b for b in blocks if b["block"] not in STATES]
    waiting = {b["name"]: {s for s in _refs(b) if s in by_name and by_name[s]["block"] not in STATES}
               for b in plain}
    readers: dict[str, list[str]] = {}
    for n, deps in waiting.items():
        for s in deps:
            readers.setdefault(s, []).append(n)
    count = {n: len(d) for n, d in waiting.items()}
    ready = [(index[n], n) for n, c in count.items() if c == 0]
    heapq.heapify(ready)
    order = []
    while ready:
        _, n = heapq.heappop(ready)
        order.append(n)
        for r in readers.get(n, ()):
            count[r] -= 1
            if count[r] == 0:
                heapq.heappush(ready, (index[r], r))
    if len(order) != len(plain):
        raise ReadingError("an algebraic loop")
    lines += [_line(f"eq {n} {prim[n]} {block_text(by_name[n])}", by_name[n]) for n in order]
    lines += [_line(f"out {f} {s}", ctrl["outports"]) for f, s in outports]
    return [x if isinstance(x, Line) else _line(x) for x in lines]
