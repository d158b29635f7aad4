"""Rules 4.2 (the node) and 4.3 (the controller): ``node.name`` and
``node.period_ms``; the controller's name, its input and output structs
and the type of each field (a primitive, or a one-dimensional array of one:
rule 4.15's controller arrays).  A controller written as a block diagram
(rule 4.11) is checked by :mod:`pyrosgen.frontend.blocks`.
"""

from __future__ import annotations

import re

from pyrosgen.errors import show
from pyrosgen.frontend.blocks import check_diagram
from pyrosgen.frontend.checker import Checker
from pyrosgen.frontend.model import MAX_CONTROLLER_ARRAY, ControllerField, Diagram
from pyrosgen.frontend.msgmodel import PRIMITIVES, ROS1_ALIASES
from pyrosgen.frontend.names import did_you_mean, identifier_problem
from pyrosgen.frontend.yamlsrc import YMap, YNode, YScalar


#: Longest accepted period (one hour).
MAX_PERIOD_MS = 3_600_000


#: At most this many fields in each of the controller's structs (rule 4.3;
#: times at the limits in BENCHMARKS.md section 5).
MAX_CONTROLLER_FIELDS = 2000


#: A controller field's type written as an array: ``float32[1081]``
#: (rule 4.15), and each of its dimensions.
_ARRAY_TYPE = re.compile(r"([^\[\]]*)((?:\[[^\[\]]*\])+)")


_DIMS = re.compile(r"\[([^\[\]]*)\]")


def node_section(ck: Checker, m: YMap | None) -> tuple[str | None, int | None]:
    """``node.name`` and ``node.period_ms`` (rule 4.2); each ``None`` when
    refused."""
    if m is None:
        return None, None
    ck.keys(m, "node", ("name", "period_ms"))
    name = ck.ident(m.get("name"), "node.name", global_scope=True)
    period = ck.integer(m.get("period_ms"), "node.period_ms", 1, MAX_PERIOD_MS, " (milliseconds)")
    return name, period


def controller_section(ck: Checker, m: YMap | None):
    """The controller section (rule 4.3): the section itself, the
    controller's name, and its inputs' and outputs' struct names and fields
    (:func:`io_struct`)."""
    if m is None:
        return None, None, (None, None), (None, None)
    ck.keys(m, "controller", ("name", "inputs", "outputs"), ("blocks", "outports", "subsystems"))
    name = ck.ident(m.get("name"), "controller.name", global_scope=True)
    uvar, ufields = io_struct(ck, ck.mapping(m.get("inputs"), "controller.inputs"), "controller.inputs")
    yvar, yfields = io_struct(ck, ck.mapping(m.get("outputs"), "controller.outputs"), "controller.outputs")
    return m, name, (uvar, ufields), (yvar, yfields)


def io_struct(ck: Checker, m: YMap | None, what: str) -> tuple[str | None, list[tuple[YScalar, ControllerField]] | None]:
    """A struct of the controller (``controller.inputs`` or ``outputs``): its
    name and its fields, each with its key's node (``None`` when any is
    refused; refused and array fields are noted on ``ck``)."""
    if m is None:
        return None, None
    ck.keys(m, what, ("name", "fields"))
    var = ck.ident(m.get("name"), f"{what}.name", global_scope=True)
    fnode = ck.mapping(m.get("fields"), f"{what}.fields")
    if fnode is None:
        return var, None
    fields: list[tuple[YScalar, ControllerField]] = []
    ok = True
    if not fnode.items:
        ck.err(fnode, f"{what}.fields must declare at least one field")
        ok = False
    elif len(fnode.items) > MAX_CONTROLLER_FIELDS:
        ck.err_rule("4.3", fnode, f"{what}.fields declares {len(fnode.items)} fields; at most "
                    f"{MAX_CONTROLLER_FIELDS} (the time to check the proof grows with the square "
                    "of a struct's width)")
        return var, None
    for knode, vnode in fnode.items:
        fname = knode.text
        problem = identifier_problem(fname)
        if problem:
            ck.err_rule("4.9", knode, f"{what}.fields: field name {show(fname)} cannot be used: {problem}")
            ok = False
            continue
        ftype = controller_type(ck, vnode, f"{what}.fields.{fname}")
        if ftype is None:
            ok = False
            ck.refused_fields.add(fname)
            continue
        fields.append((knode, ControllerField(fname, *ftype)))
        if ftype[1] is not None:
            ck.array_fields.add(fname)
    return var, fields if ok else None


def controller_type(ck: Checker, node: YNode, what: str) -> tuple[str, int | None] | None:
    """The type of a controller field written at ``node``: a primitive
    (``float64``: ``(prim, None)``) or a one-dimensional array of one
    (``float32[1081]``: ``(prim, 1081)``, rule 4.15); ``None``
    (reported) when it is neither."""
    t = ck.string(node, f"type of {what}")
    if t is None:
        return None
    m = _ARRAY_TYPE.fullmatch(t)
    if m is None:
        prim = prim_type(ck, node, what)
        return (prim, None) if prim is not None else None
    base, dims = m.group(1), _DIMS.findall(m.group(2))
    rule = "4.15"
    example = f"{base}[8]" if base in PRIMITIVES else "float32[8]"
    if base not in PRIMITIVES:
        # the element type's problem, as for a scalar field (rule 4.3)
        if base in ROS1_ALIASES:
            ck.err_rule("4.3", node, f"{what}: type {show(t)}: {show(base)} is a deprecated ROS alias; "
                                     f"write {ROS1_ALIASES[base]}{m.group(2)}")
        elif base in ("string", "time", "duration") or "/" in base:
            ck.err_rule("4.3", node, f"{what}: type {show(t)} is not allowed: a controller array has "
                                     f"elements of a primitive type (expected one of {', '.join(PRIMITIVES)})")
        else:
            ck.err_rule("4.3", node, f"{what}: unknown element type {show(base)} in {show(t)}"
                                     f"{did_you_mean(base, PRIMITIVES)}; expected one of "
                                     f"{', '.join(PRIMITIVES)}")
        return None
    if len(dims) > 1:
        ck.err_rule(rule, node, f"{what}: type {show(t)} is an array of {len(dims)} dimensions; a "
                                f"controller array has one (e.g. {show(example)}: flatten it)")
        return None
    dim = dims[0]
    if dim == "":
        ck.err_rule(rule, node, f"{what}: type {show(t)} is a variable-length array; a controller "
                                f"array has a fixed size, an integer from 1 to {MAX_CONTROLLER_ARRAY} "
                                f"(e.g. {show(example)}; a variable-length array of a message is read "
                                "into one, rule 4.15)")
        return None
    if not re.fullmatch(r"0|[1-9][0-9]{0,8}", dim):
        ck.err_rule(rule, node, f"{what}: type {show(t)}: the size {show(dim)} is not an integer; a "
                                f"controller array has a size from 1 to {MAX_CONTROLLER_ARRAY} "
                                f"(e.g. {show(example)})")
        return None
    n = int(dim)
    if not 1 <= n <= MAX_CONTROLLER_ARRAY:
        ck.err_rule(rule, node, f"{what}: type {show(t)}: a controller array has a size from 1 to "
                                f"{MAX_CONTROLLER_ARRAY}, got {n}")
        return None
    return base, n


def prim_type(ck: Checker, node: YNode, what: str) -> str | None:
    """The primitive type written at ``node`` for field ``what`` (rule 4.3),
    or ``None`` (reported)."""
    t = ck.string(node, f"type of {what}")
    if t is None:
        return None
    if t in PRIMITIVES:
        return t
    expected = f"expected one of {', '.join(PRIMITIVES)}"
    if t in ROS1_ALIASES:
        ck.err_rule("4.3", node, f"{what}: type {show(t)} is a deprecated ROS alias; write {ROS1_ALIASES[t]}")
    elif t in ("string", "time", "duration") or "/" in t or "[" in t:
        ck.err_rule("4.3", node, f"{what}: type {show(t)} is not allowed: controller fields have primitive types ({expected})")
    else:
        ck.err_rule("4.3", node, f"{what}: unknown type {show(t)}{did_you_mean(t, PRIMITIVES)}; {expected}")
    return None


def check_controller_diagram(ck: Checker, cm: YMap | None, ctrl_name, ufields, yfields, uvar, yvar,
                             period) -> Diagram | None:
    """A controller written as a block diagram (rule 4.11,
    :func:`pyrosgen.frontend.blocks.check_diagram`): its inputs and outputs
    are scalars (rule 4.15).  Returns the diagram, or ``None`` (none, or
    refused)."""
    arrays = [(knode, f, side) for side, fields in (("inputs", ufields), ("outputs", yfields))
              for knode, f in (fields or ()) if f.is_array]
    if cm is not None and (cm.get("blocks") is not None or cm.get("outports") is not None) and arrays:
        for knode, f, side in arrays:
            ck.err_rule("4.15", knode,
                        f"controller.{side}.fields.{f.name}: a block diagram's inputs and outputs are scalars; "
                        f"the array {f.name} ({f.type_text}) is for a controller brought in C (declare "
                        f"{f.size} scalar fields for the diagram)")
        return None
    return check_diagram(ck, cm, ctrl_name, ufields, yfields, uvar, yvar, period)
