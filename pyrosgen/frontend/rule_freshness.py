"""Rule 4.12 (freshness): topics' ``timeout_ms`` and ``on_timeout``, input
relations' fallbacks (``on_timeout``) and derived inputs (``is_new``,
``received``, ``age_ms``); with rule 4.15, a controller array has no
fallback.
"""

from __future__ import annotations

from dataclasses import replace

from pyrosgen.errors import show
from pyrosgen.frontend.blocks import scalar_of, zero
from pyrosgen.frontend.checker import Checker, Rel, TopicDecl
from pyrosgen.frontend.model import (
    DERIVED_KINDS, DERIVED_PRIMS, MAX_TIMEOUT_MS, ON_TIMEOUT_POLICIES, PUBLISH, SEQUENCE_DERIVED,
    ControllerField, Scalar,
)
from pyrosgen.frontend.names import did_you_mean
from pyrosgen.frontend.yamlsrc import YBad, YNode, YScalar


def check_freshness(ck: Checker, decls: list[TopicDecl], in_rels: list[Rel],
                    inputs: dict[str, ControllerField] | None, period: int | None) -> set[str]:
    """Rule 4.12: topics' ``timeout_ms`` and ``on_timeout``, input
    relations' ``on_timeout`` (their fallbacks, set on each relation) and
    derived inputs.  Returns the names of the *timed* topics (a
    ``timeout_ms`` or a derived input): the glue keeps the globals
    ``<c>_time``, ``<c>_new`` and ``<c>_rcvd`` for each (rule 4.9)."""
    timed: set[str] = set()
    for d in decls:
        if _topic_timeout(ck, d, period):
            timed.add(d.name)
    for i, r in enumerate(in_rels):
        w = f"relations.inputs[{i}]"
        if r.is_derived:
            _derived_input(ck, r, w, inputs)
            if r.topic is not None:
                timed.add(r.topic.name)
        else:
            _input_fallback(ck, r, w, inputs)
    return timed


def _topic_timeout(ck: Checker, d: TopicDecl, period: int | None) -> bool:
    """Topic ``d``'s ``timeout_ms`` and ``on_timeout`` (sets them on ``d``);
    whether it has a ``timeout_ms`` (valid or not)."""
    rule = "4.12"
    what = d.what
    tnode, pnode = d.node.get("timeout_ms"), d.node.get("on_timeout")
    if tnode is not None:
        d.timeout_ms = _timeout(ck, d, tnode, what, period)
    if pnode is not None and not isinstance(pnode, YBad):
        if tnode is None:
            ck.err_rule(rule, pnode, f"{what}.on_timeout is only allowed together with timeout_ms "
                                     "(the topic has no timeout)")
        if isinstance(pnode, YScalar) and pnode.kind == "str" and pnode.value in ON_TIMEOUT_POLICIES:
            d.policy = pnode.value
        else:
            hint = (did_you_mean(pnode.value, ON_TIMEOUT_POLICIES) if isinstance(pnode, YScalar)
                    and pnode.kind == "str" else "")
            if not hint and isinstance(pnode, YScalar) and pnode.kind in ("int", "float", "bool"):
                hint = " (a constant fallback is given by an input relation's on_timeout)"
            ck.err_rule(rule, pnode, f"{what}.on_timeout must be 'hold' or 'zero', got {pnode.describe()}{hint}")
    return tnode is not None


def _derived_input(ck: Checker, r: Rel, w: str, inputs: dict[str, ControllerField] | None) -> None:
    """Derived input ``r`` (``is_new``, ``received``, ``age_ms``): no field,
    no fallback, a known kind, feeding a scalar input of its type."""
    rule = "4.12"
    m = r.node
    onode = m.get("on_timeout")
    fnode = m.get("field")
    if fnode is not None:
        ck.err_rule(rule, fnode, f"{w}.field: a derived input reads no message field "
                                 "(a relation has either field or derived; field goes with derived: "
                                 "length or truncated only)")
        r.ok = False
    if onode is not None:
        ck.err_rule(rule, onode, f"{w}.on_timeout: a derived input has no fallback "
                                 "(it does not read a message field)")
        r.ok = False
    dnode = m.get("derived")
    if isinstance(dnode, YBad):
        r.ok = False
    elif isinstance(dnode, YScalar) and dnode.kind == "str" and dnode.value in DERIVED_KINDS:
        r.derived = dnode.value
    else:
        hint = (did_you_mean(dnode.value, DERIVED_KINDS)
                if isinstance(dnode, YScalar) and dnode.kind == "str" else "")
        hint = hint or (did_you_mean(dnode.value, tuple(SEQUENCE_DERIVED))
                        if isinstance(dnode, YScalar) and dnode.kind == "str" else "")
        ck.err_rule(rule, dnode, f"{w}.derived must be 'is_new', 'received' or 'age_ms' (or, with a "
                                 f"field, 'length' or 'truncated'), got {dnode.describe()}{hint}")
        r.ok = False
    if r.ctrl_field is not None and inputs is not None and inputs[r.ctrl_field].is_array:
        f = inputs[r.ctrl_field]
        target = f.name if r.ctrl_index is None else f"{f.name}[{r.ctrl_index}]"
        ck.err_rule("4.15", r.ctrl_node,
                    f"{w}.input: a derived input feeds a scalar controller input; {show(target)} is "
                    f"{'an element of ' if r.ctrl_index is not None else ''}the array {f.name} "
                    f"({f.type_text})")
        r.ok = False
    elif r.derived is not None and r.ctrl_field is not None and inputs is not None:
        need, prim = DERIVED_PRIMS[r.derived], inputs[r.ctrl_field].prim
        if prim != need:
            ck.err_rule(rule, r.ctrl_node,
                        f"{w}.input: {r.derived} related to a non-{need} field: controller input "
                        f"{show(r.ctrl_field)} is {prim} ({r.derived} is a {need})")
            r.ok = False


def _input_fallback(ck: Checker, r: Rel, w: str, inputs: dict[str, ControllerField] | None) -> None:
    """The ``on_timeout`` of plain input relation ``r``: ``hold``, ``zero``
    or a constant of its input's type (set as ``r.fallback``), on a topic
    with a timeout; a controller array has none (rule 4.15)."""
    rule = "4.12"
    onode = r.node.get("on_timeout")
    if r.ctrl_field is not None and inputs is not None and inputs[r.ctrl_field].is_array:
        _array_fallback(ck, r, w, inputs[r.ctrl_field])
        return
    if onode is None or isinstance(onode, YBad):
        return
    if r.topic is not None and r.topic.node.get("timeout_ms") is None:
        ck.err_rule(rule, onode, f"{w}.on_timeout: topic {show(r.topic.name)} has no timeout_ms; "
                                 "a fallback needs one")
        r.ok = False
    if isinstance(onode, YScalar) and onode.kind == "str" and onode.value in ON_TIMEOUT_POLICIES:
        return
    if r.ctrl_field is None or inputs is None:
        return  # the input is reported, and its type unknown
    prim = inputs[r.ctrl_field].prim
    value, problem = fallback_constant(onode, prim)
    if problem is not None:
        hint = (did_you_mean(onode.value, ON_TIMEOUT_POLICIES)
                if isinstance(onode, YScalar) and onode.kind == "str" else "")
        if hint or (isinstance(onode, YScalar) and onode.kind == "str" and "YAML 1.1" not in problem):
            ck.err_rule(rule, onode, f"{w}.on_timeout must be 'hold', 'zero' or a constant of type {prim} "
                                     f"(the type of controller input {show(r.ctrl_field)}), "
                                     f"got {onode.describe()}{hint}")
        else:
            ck.err_rule(rule, onode, f"{w}.on_timeout: the fallback of controller input "
                                     f"{show(r.ctrl_field)} ({prim}): {problem}")
        r.ok = False
    else:
        r.fallback = value


def _array_fallback(ck: Checker, r: Rel, w: str, f: ControllerField) -> None:
    """Rule 4.15 (and 4.12): a relation feeding a controller array, whole or
    one element, has no fallback: its ``on_timeout`` (or else its topic's,
    when the topic has a timeout) is ``hold``."""
    onode = r.node.get("on_timeout")
    target = f.name if r.ctrl_index is None else f"{f.name}[{r.ctrl_index}]"
    if isinstance(onode, YBad):
        r.ok = False
        return
    if onode is not None:
        if isinstance(onode, YScalar) and onode.kind == "str" and onode.value == "hold":
            if r.topic is not None and r.topic.node.get("timeout_ms") is None:
                ck.err_rule("4.12", onode, f"{w}.on_timeout: topic {show(r.topic.name)} has no timeout_ms; "
                                           "a fallback needs one")
                r.ok = False
            return
        ck.err_rule("4.15", onode, f"{w}.on_timeout: controller input {show(target)} is "
                                   f"{'an element of ' if r.ctrl_index is not None else ''}the array {f.name} "
                                   f"({f.type_text}), which has no fallback (fallbacks feed scalar inputs): "
                                   "write on_timeout: hold")
        r.ok = False
        return
    if r.topic is not None and r.topic.timeout_ms is not None and r.topic.policy != "hold":
        ck.err_rule("4.15", r.ctrl_node, f"{w}.input: topic {show(r.topic.name)} has a timeout with on_timeout "
                                         f"{r.topic.policy}, which gives each input it feeds a fallback, but "
                                         f"{show(target)} is {'an element of ' if r.ctrl_index is not None else ''}"
                                         f"the array {f.name} ({f.type_text}), which has none (fallbacks feed "
                                         "scalar inputs): write on_timeout: hold on this relation or on the topic")
        r.ok = False


def _timeout(ck: Checker, d: TopicDecl, node: YNode, what: str, period: int | None) -> int | None:
    """The ``timeout_ms`` of topic ``d`` written at ``node``, or ``None``
    (reported) when it is not a valid one (rule 4.12)."""
    rule = "4.12"
    if isinstance(node, YBad):
        return None
    if d.direction == PUBLISH:
        ck.err_rule(rule, node, f"{what}.timeout_ms: topic {show(d.name)} is published by the node; "
                                "a timeout is for a subscribed topic")
        return None
    if not (isinstance(node, YScalar) and node.kind == "int"):
        ck.err_rule(rule, node, f"{what}.timeout_ms must be an integer number of milliseconds, "
                                f"got {node.describe()}")
        return None
    v = node.value
    if v <= 0:
        ck.err_rule(rule, node, f"{what}.timeout_ms must be a positive number of milliseconds, got {show(node.text)}")
        return None
    if v > MAX_TIMEOUT_MS:
        ck.err_rule(rule, node, f"{what}.timeout_ms: {node.text} ms is longer than a day "
                                f"(at most {MAX_TIMEOUT_MS})")
        return None
    if period is not None and v < period:
        ck.err_rule(rule, node, f"{what}.timeout_ms: {node.text} ms is a timeout shorter than the period "
                                f"(node.period_ms is {period})")
        return None
    return v


#: The ranges of the integer types that a fallback may have but a
#: diagram's constant may not (:func:`pyrosgen.frontend.blocks.scalar_of`
#: reads the others).
_NARROW_INT_RANGES = {
    "int8": (-(1 << 7), (1 << 7) - 1),
    "uint8": (0, (1 << 8) - 1),
    "int16": (-(1 << 15), (1 << 15) - 1),
    "uint16": (0, (1 << 16) - 1),
}


def fallback_constant(node: YNode, prim: str) -> tuple[Scalar | None, str | None]:
    """The constant of type ``prim`` (any ROS primitive) written at
    ``node``, or why it is not one: read as rule 4.11 reads a diagram's
    constants (:func:`pyrosgen.frontend.blocks.scalar_of`): an integer in
    the type's range (a float is refused for an integer type), a float
    rounded once, to nearest even, from the exact decimal, ``true`` or
    ``false`` for ``bool``."""
    if prim in _NARROW_INT_RANGES and isinstance(node, YScalar) and node.kind in ("int", "float"):
        if node.kind != "int":
            return None, f"{show(node.text)} is not an integer, and the type is {prim}"
        lo, hi = _NARROW_INT_RANGES[prim]
        if not lo <= node.value <= hi:
            return None, f"{node.text} is out of the range of {prim} ({lo} to {hi})"
        return Scalar(prim, node.value, node.text), None
    return scalar_of(node, prim)


def fallback_of(r: Rel, prim: str) -> Scalar | None:
    """The value a plain input relation's input gets when its topic is
    stale (rule 4.12): the relation's ``on_timeout`` or else its topic's
    (default ``zero``: the zero of the input's type); ``None`` for
    ``hold`` and for a topic without a timeout."""
    if r.topic.timeout_ms is None:
        return None
    if r.fallback is not None:
        return r.fallback
    onode = r.node.get("on_timeout")
    policy = onode.value if isinstance(onode, YScalar) and onode.kind == "str" else r.topic.policy
    return replace(zero(prim), text="zero") if policy == "zero" else None
