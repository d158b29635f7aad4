"""Rules 4.6 (field paths) and 4.7 (relations): each input and output
relation names a topic of the right direction, a controller field (or one
element of a controller array, rule 4.15) and a field path of the topic's
message, of the same type (relations never convert).  A whole-array row
(rule 4.15) is checked by :mod:`pyrosgen.frontend.rule_arrays`, a derived
input (rule 4.12) by :mod:`pyrosgen.frontend.rule_freshness`.
"""

from __future__ import annotations

import re

from pyrosgen.errors import show
from pyrosgen.frontend.checker import Checker, Rel, TopicDecl, name_list
from pyrosgen.frontend.model import PUBLISH, SEQUENCE_DERIVED, SUBSCRIBE, ControllerField
from pyrosgen.frontend.msgload import BoundedPathError, MsgRegistry, PathError, StringPathError
from pyrosgen.frontend.msgmodel import FieldPath
from pyrosgen.frontend.names import did_you_mean
from pyrosgen.frontend.rule_arrays import whole_array, whole_array_row
from pyrosgen.frontend.yamlsrc import YBad, YNode, YScalar, YSeq


#: The keys of an input relation: `field` for a plain one, `derived` for a
#: derived input (rule 4.12).
_INPUT_KEYS = ("topic", "field", "input", "on_timeout", "derived")


def relations_section(
    ck,
    node: YNode | None,
    topics: dict[str, TopicDecl],
    inputs: dict[str, ControllerField] | None,
    outputs: dict[str, ControllerField] | None,
    registry: MsgRegistry,
) -> tuple[list[Rel], list[Rel]]:
    """The ``relations`` section: its input and output rows
    (:func:`relation_rows`)."""
    m = ck.mapping(node, "relations")
    if m is None:
        return [], []
    ck.keys(m, "relations", ("inputs",), ("outputs",))
    rows = m.get("inputs")
    ck.inputs_listed = isinstance(rows, YSeq) or (isinstance(rows, YScalar) and rows.kind == "null")
    ins = relation_rows(ck, m.get("inputs"), "relations.inputs", "input", topics, inputs, outputs, registry)
    outs = relation_rows(ck, m.get("outputs"), "relations.outputs", "output", topics, outputs, inputs, registry)
    return ins, outs


def relation_rows(ck: Checker, node, what, kind, topics, ctrl, other, registry) -> list[Rel]:
    """The rows of ``relations.inputs`` or ``relations.outputs`` written
    at ``node`` (``kind``: input or output), each as far as it checks:
    its topic (subscribed for an input, published for an output), its
    controller field (of ``ctrl``; ``other``, the other side's, for a
    hint), its field path and their types (rules 4.6, 4.7, 4.15)."""
    if node is None or isinstance(node, YBad):
        return []
    if isinstance(node, YScalar) and node.kind == "null":
        return []
    if not isinstance(node, YSeq):
        ck.err(node, f"{what} must be a list of relations, got {node.describe()}")
        return []
    want_dir = SUBSCRIBE if kind == "input" else PUBLISH
    out = []
    for i, item in enumerate(node.items):
        w = f"{what}[{i}]"
        m = ck.mapping(item, w)
        if m is None:
            continue
        rel = _row_kind(ck, m, w, kind)
        out.append(rel)
        _row_topic(ck, rel, m, w, kind, topics, want_dir)
        if not _row_controller_field(ck, rel, m, w, kind, ctrl, other):
            continue  # its type is refused or its struct is: what it relates to is unknown
        if rel.is_derived:
            continue  # its kind and type: check_freshness
        ptext = _row_field(ck, rel, m, w, kind, ctrl, registry)
        _row_types(ck, rel, m, w, kind, ctrl, ptext)
    return out


def _row_kind(ck: Checker, m: YMap, w: str, kind: str) -> Rel:
    """The row ``w`` written at ``m``, with its keys checked: a plain
    relation, a derived input (rule 4.12) or a length or truncated flag
    (rule 4.15)."""
    rel = Rel(m)
    if kind == "input":
        # a derived input (rule 4.12) has no field; `field` and
        # `on_timeout` with it are refused by check_freshness; but
        # `derived: length` and `derived: truncated` name the
        # variable-length array or string they read with `field`
        # (rule 4.15)
        dnode = m.get("derived")
        if isinstance(dnode, YScalar) and dnode.kind == "str" and dnode.value in SEQUENCE_DERIVED:
            rel.seq_kind = dnode.value
        rel.is_derived = dnode is not None and rel.seq_kind is None
        required = (("topic", "derived", "input") if rel.is_derived else ("topic", "input")
                    if rel.seq_kind else ("topic", "field", "input"))
        ck.keys(m, w, required, tuple(k for k in _INPUT_KEYS if k not in required))
    else:
        # an output relation into a published variable-length array
        # or string writes one element (field: "data[3]") or, with
        # derived: length, its length (rule 4.15)
        dnode = m.get("derived")
        if dnode is not None:
            if isinstance(dnode, YScalar) and dnode.kind == "str" and dnode.value == "length":
                rel.seq_kind = "length"
            else:
                ck.err_rule("4.15", dnode, f"{w}.derived: {_output_derived_problem(dnode)}")
                rel.ok = False
        ck.keys(m, w, ("output", "topic", "field"), ("derived",))
    rel.what = w
    return rel


def _row_topic(ck: Checker, rel: Rel, m: YMap, w: str, kind: str, topics, want_dir: str) -> None:
    """The row's topic: declared, of direction ``want_dir``, usable."""
    tnode = m.get("topic")
    tname = ck.string(tnode, f"{w}.topic")
    if tname is None:
        rel.ok = False
    elif tname not in topics:
        if ck.topics_listed:
            ck.err(
                tnode,
                f"{w}.topic: unknown topic {show(tname)}{did_you_mean(tname, list(topics))}; declare it under topics",
            )
        rel.ok = False
    else:
        decl = topics[tname]
        if decl.direction is not None and decl.direction != want_dir:
            if rel.is_derived:
                ck.err_rule("4.12", tnode, f"{w}.topic: topic {show(tname)} is published by the node; "
                                           "a derived input reads a subscribed topic")
            elif kind == "input":
                ck.err(tnode, f"{w}.topic: topic {show(tname)} is published by the node; "
                              "an input relation reads a subscribed topic")
            else:
                ck.err(tnode, f"{w}.topic: topic {show(tname)} is subscribed by the node; "
                              "an output relation writes a published topic")
            rel.ok = False
        elif not decl.usable:
            rel.ok = False
        else:
            rel.topic = decl


def _row_controller_field(ck: Checker, rel: Rel, m: YMap, w: str, kind: str, ctrl, other) -> bool:
    """The row's controller field (or element of a controller array, rule
    4.15); ``False`` when the row is not checked further (the field's
    type, or its struct, is refused)."""
    cnode = m.get(kind)
    cname = ck.string(cnode, f"{w}.{kind}")
    rel.ctrl_node = cnode
    if cname is None:
        rel.ok = False
    elif ctrl is not None:
        base, index = split_target(cname)
        if base in ctrl and index is not None and not ctrl[base].is_array:
            ck.err_rule("4.15", cnode,
                        f"{w}.{kind}: {show(cname)} names an element of controller {kind} {show(base)}, "
                        f"which is not an array (it is {prim_article(ctrl[base].prim)} "
                        f"{ctrl[base].prim}): write {show(base)}")
            rel.ok = False
            rel.ctrl_field = base  # it is fed (by a refused relation)
        elif base in ctrl and index is not None and index >= ctrl[base].size:
            f = ctrl[base]
            ck.err_rule("4.15", cnode,
                        f"{w}.{kind}: index {index} is beyond controller {kind} {show(base)} "
                        f"({f.type_text}): valid indices are 0..{f.size - 1}")
            rel.ok = False
        elif base in ctrl:
            rel.ctrl_field, rel.ctrl_index = base, index
        else:
            hint = ""
            if other is not None and cname in other:
                otherkind = "output" if kind == "input" else "input"
                hint = f" ({show(cname)} is a controller {otherkind})"
            else:
                hint = did_you_mean(cname, list(ctrl))
            ck.err_rule(
                "4.7",
                cnode,
                f"{w}.{kind}: {show(cname)} is not a controller {kind}{hint}; "
                f"controller {kind}s are {name_list(ctrl)}",
            )
            rel.ok = False
    else:
        rel.ok = False
        if cname is not None and split_target(cname)[0] in ck.refused_fields | ck.array_fields:
            return False  # its type is refused or its struct is: what it relates to is unknown
    return True


def _row_field(ck: Checker, rel: Rel, m: YMap, w: str, kind: str, ctrl, registry: MsgRegistry) -> str | None:
    """The row's field path, resolved in its topic's message type (rule
    4.6); returns the path as written (``None``: none)."""
    pnode = m.get("field")
    rel.path_node = pnode
    ptext = None
    if rel.seq_kind is not None and pnode is None and kind == "input":
        ck.err_rule("4.15", m.get("derived"),
                    f"{w}.derived: {rel.seq_kind} reads a variable-length array or a string: name it "
                    "with field (e.g. field: ranges)")
    if pnode is not None and not isinstance(pnode, YBad):
        ptext = ck.string(pnode, f"{w}.field")
    if ptext is None:
        rel.ok = False
    elif kind == "output" and m.get("derived") is not None and rel.seq_kind is None:
        if rel.topic is not None:  # the relation is refused; what it names (check_published_sequences)
            rel.bounded = registry.bounded_in_path(rel.topic.msg_type, ptext)
    elif rel.topic is not None:
        try:
            _resolve_field(ck, rel, m, w, kind, ctrl, registry, ptext)
        except PathError as exc:
            _field_refused(ck, rel, pnode, w, kind, ctrl, registry, ptext, exc)
    return ptext


def _resolve_field(ck: Checker, rel: Rel, m: YMap, w: str, kind: str, ctrl, registry: MsgRegistry,
                   ptext: str) -> None:
    """Resolve field path ``ptext`` of the row: the length or truncated
    flag of a variable-length array or string, a whole array related to a
    whole controller array (rule 4.15), or a leaf; raises
    :class:`PathError` when it names none."""
    if rel.seq_kind is not None:
        target = registry.walk_bounded(rel.topic.msg_type, ptext, f"derived: {rel.seq_kind}")
        leaf, prim = SEQUENCE_DERIVED[rel.seq_kind]
        rel.path = FieldPath((*target.steps, leaf), prim)
        rel.bounded = target
        rel.written = f"{ptext} ({rel.seq_kind})"
        if rel.seq_kind == "truncated" and target.key in registry.carry_reject:
            ck.err_rule("4.15", m.get("derived"),
                        f"{w}.derived: truncated of {ptext}, whose policy is reject, is always 0 "
                        f"(a longer message is not delivered): use derived: length, or policy "
                        f"truncate ({target.field} of {target.owner})")
            rel.ok = False
    elif rel.ctrl_field is not None and ctrl[rel.ctrl_field].is_array and rel.ctrl_index is None:
        whole_array_row(ck, rel, ptext, registry, kind, ctrl[rel.ctrl_field])
    else:
        rel.path = registry.walk_path(rel.topic.msg_type, ptext, bounded=True,
                                      writes=kind == "output")
        rel.bounded = registry.bounded_in_path(rel.topic.msg_type, ptext)
        if rel.bounded is not None:
            rel.written = ptext


def _field_refused(ck: Checker, rel: Rel, pnode, w: str, kind: str, ctrl, registry: MsgRegistry, ptext: str,
                   exc: PathError) -> None:
    """Report why field path ``ptext`` of the row names no field it can
    relate (``exc``)."""
    if kind == "output":  # refused; what it names (check_published_sequences)
        rel.bounded = registry.bounded_in_path(rel.topic.msg_type, ptext)
    arr = (whole_array(registry, rel.topic.msg_type, ptext)
           if rel.ctrl_field is not None and rel.seq_kind is None else None)
    if arr is not None and arr.kind == "fixed":
        # a whole fixed-size array and a scalar (rule 4.15)
        cf = ctrl[rel.ctrl_field]
        target = f"{rel.ctrl_field}[{rel.ctrl_index}]" if rel.ctrl_index is not None else rel.ctrl_field
        ck.err_rule("4.15", pnode,
                    f"{w}.field: {show(ptext)} of topic {show(rel.topic.name)} is a whole array "
                    f"({arr.type_text}) but controller {kind} {show(target)} is one {cf.prim}: "
                    f"relate one element ({show(ptext + '[0]')}), or the whole array to a "
                    f"controller array of {arr.size} {arr.prim}")
    else:
        rule = ("4.15" if isinstance(exc, BoundedPathError) or rel.seq_kind is not None
                else "4.14" if isinstance(exc, StringPathError) else "4.6")
        ck.err_rule(rule, pnode, f"{w}.field: {exc.args[0]} (topic {show(rel.topic.name)}, {rel.topic.msg_type})")
    rel.ok = False


def _row_types(ck: Checker, rel: Rel, m: YMap, w: str, kind: str, ctrl, ptext: str | None) -> None:
    """The row's field and controller field have the same type (relations
    never convert; rules 4.7, 4.15)."""
    if rel.elements is not None:
        return  # a whole array: checked by whole_array_row
    if (rel.seq_kind is not None and rel.ctrl_field is not None and ctrl[rel.ctrl_field].is_array
            and rel.ctrl_index is None):
        cf = ctrl[rel.ctrl_field]
        ck.err_rule("4.15", rel.ctrl_node,
                    f"{w}.{kind}: {rel.seq_kind} is one {SEQUENCE_DERIVED[rel.seq_kind][1]} but controller "
                    f"{kind} {show(cf.name)} is an array ({cf.type_text}): relate it to a scalar {kind}, "
                    f"or to one element ({show(cf.name + '[0]')})")
        rel.ok = False
        return
    if rel.path is not None and rel.ctrl_field is not None:
        cprim = ctrl[rel.ctrl_field].prim
        if cprim != rel.path.prim and rel.seq_kind is not None and kind == "output":
            what_ = "string" if rel.bounded.is_string else "variable-length array"
            ck.err_rule("4.15", rel.ctrl_node,
                        f"{w}.output: the length of a published {what_} is a uint32: controller output "
                        f"{show(rel.ctrl_field)} is {cprim} (relations never convert)")
            rel.ok = False
        elif cprim != rel.path.prim and rel.seq_kind is not None:
            ck.err_rule("4.15", rel.ctrl_node,
                        f"{w}.input: {rel.seq_kind} related to a non-{rel.path.prim} field: controller "
                        f"input {show(rel.ctrl_field)} is {cprim} ({rel.seq_kind} is a {rel.path.prim})")
            rel.ok = False
        elif cprim != rel.path.prim and rel.bounded is not None and rel.bounded.is_string:
            if kind == "input":
                msg = (f"{w}: a string related to a non-uint8 field: {show(ptext)} of topic "
                       f"{show(rel.topic.name)} is a byte of a string (uint8) but controller input "
                       f"{show(rel.ctrl_field)} is {cprim} (a string reaches the controller byte by "
                       "byte, as uint8, with its length from derived: length)")
            else:
                msg = (f"{w}: a string related to a non-uint8 field: controller output "
                       f"{show(rel.ctrl_field)} is {cprim} but {show(ptext)} of topic "
                       f"{show(rel.topic.name)} is a byte of a string (uint8) (a published string "
                       "takes its bytes from uint8 outputs and its length from a uint32 output, "
                       "derived: length)")
            ck.err_rule("4.15", m, msg)
            rel.ok = False
        elif cprim != rel.path.prim:
            if kind == "input":
                msg = (
                    f"{w}: type mismatch: field {show(rel.written or str(rel.path))} of topic "
                    f"{show(rel.topic.name)} is {rel.path.prim} but controller input "
                    f"{show(rel.ctrl_field)} is {cprim} (relations never convert)"
                )
            else:
                msg = (
                    f"{w}: type mismatch: controller output {show(rel.ctrl_field)} is "
                    f"{cprim} but field {show(str(rel.path))} of topic "
                    f"{show(rel.topic.name)} is {rel.path.prim} (relations never convert)"
                )
            # an element of a variable-length array: rule 4.15's
            ck.err_rule("4.15" if rel.bounded is not None else "4.7", m, msg)
            rel.ok = False


def split_target(text: str) -> tuple[str, int | None]:
    """A relation's controller field as written: ``Scan[540]`` is element
    540 of ``Scan`` (rule 4.15), ``In1`` the field itself; anything else is
    returned as it is (and is no controller field)."""
    m = re.fullmatch(r"([A-Za-z_][A-Za-z0-9_]*)\[(0|[1-9][0-9]{0,8})\]", text)
    return (m.group(1), int(m.group(2))) if m else (text, None)


def prim_article(prim: str) -> str:
    """The article of a primitive type's name as read aloud: an int8, a uint8."""
    return "an" if prim[:1] in "aeio" else "a"


def _output_derived_problem(dnode: YNode) -> str:
    """Why the ``derived`` of an output relation, written at ``dnode``, is
    not ``length`` (the only kind on the publish side, rule 4.15)."""
    if isinstance(dnode, YScalar) and dnode.kind == "str" and dnode.value == "truncated":
        return ("an output relation does not write truncated: on publish it is meaningless (the subscriber "
                "receives the first min(length, N) elements and the environment model recomputes the flag); "
                "write the length with derived: length")
    got = show(dnode.value) if isinstance(dnode, YScalar) and dnode.kind == "str" else dnode.describe()
    return (f"an output relation takes derived: length only (the length of a published variable-length "
            f"array or string, from a uint32 output), got {got}")
