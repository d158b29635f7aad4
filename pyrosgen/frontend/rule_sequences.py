"""Rule 4.15, variable-length arrays and strings of messages: a topic's
``max_length`` and ``policy`` (one value per field of a message type), and,
on the publish side, the length of every published array or string whose
elements the controller writes.
"""

from __future__ import annotations

from dataclasses import dataclass

from pyrosgen.errors import show
from pyrosgen.frontend.checker import Checker, Rel, TopicDecl
from pyrosgen.frontend.model import PUBLISH
from pyrosgen.frontend.msgload import BoundedTarget, MsgRegistry, PathError
from pyrosgen.frontend.msgmodel import MAX_SEQUENCE_LENGTH
from pyrosgen.frontend.names import did_you_mean
from pyrosgen.frontend.rule_strings import steps_text
from pyrosgen.frontend.yamlsrc import YBad, YMap, YNode, YScalar


@dataclass
class _MaxItem:
    """An entry of a topic's ``max_length`` (rule 4.15): ``what`` names it
    in messages, ``key`` is its field path's node, ``value`` its value's;
    ``target`` the sequence or string it names, or ``problem`` why its
    path names none; ``n`` its maximum, or ``value_problem`` why it is not
    one."""

    what: str
    key: YNode
    value: YNode
    target: BoundedTarget | None = None
    problem: str | None = None
    n: int | None = None
    value_problem: str | None = None


def _max_value(node: YNode) -> tuple[int | None, str | None]:
    """The maximum length written at ``node``, or why it is not one: an
    integer from 1 to :data:`MAX_SEQUENCE_LENGTH`."""
    expected = f"an integer from 1 to {MAX_SEQUENCE_LENGTH}"
    if not (isinstance(node, YScalar) and node.kind == "int"):
        return None, f"must be {expected} (the most elements carried), got {node.describe()}"
    if node.value < 1:
        return None, (f"must be {expected}, got {show(node.text)} (a carried array holds at least one "
                      "element; its received length may still be 0)")
    if node.value > MAX_SEQUENCE_LENGTH:
        return None, f"must be {expected}, got {show(node.text)}"
    return node.value, None


def max_length_items(mnode: YMap, msg_type: str | None, registry: MsgRegistry, what: str) -> list[_MaxItem]:
    """The entries of the ``max_length`` mapping ``mnode`` of a topic of
    ``msg_type`` (``None``: unknown, the paths are not resolved)."""
    out = []
    for k, v in mnode.items:
        it = _MaxItem(f"{what}.max_length[{show(k.text)}]", k, v)
        if not isinstance(v, YBad):
            it.n, it.value_problem = _max_value(v)
        if k.kind != "str":
            it.problem = f"a key of max_length is a field path, got {k.describe()}"
        elif msg_type is not None:
            try:
                it.target = registry.walk_bounded(msg_type, k.value, "max_length")
            except PathError as exc:
                it.problem = exc.args[0]
        out.append(it)
    return out


def check_max_length(ck: Checker, decls: list[TopicDecl], registry: MsgRegistry) -> None:
    """Rule 4.15: a topic's ``max_length: {<field path>: N}`` names
    variable-length arrays of primitives or ``string`` fields of its
    message (through nested messages and fixed-size arrays of messages),
    each with an integer ``N`` from 1 to :data:`MAX_SEQUENCE_LENGTH`; one
    field of a message type (held by one C struct in every topic of the
    type) gets one maximum."""
    rule = "4.15"
    seen: dict[tuple[str, str], tuple[_MaxItem, int]] = {}
    for d in decls:
        mnode = d.node.get("max_length")
        if mnode is None or isinstance(mnode, YBad):
            continue
        if not isinstance(mnode, YMap):
            ck.err_rule(rule, mnode, f"{d.what}.max_length must be a mapping of field paths to maximum lengths "
                                     f"(e.g. {{ranges: 1081}}), got {mnode.describe()}")
            continue
        msg_type = d.msg_type if d.msg_type is not None and registry.raw(d.msg_type) is not None else None
        for it in max_length_items(mnode, msg_type, registry, d.what):
            if it.value_problem is not None:
                ck.err_rule(rule, it.value, f"{it.what} {it.value_problem}")
            if msg_type is None:
                continue  # the type is reported
            if it.problem is not None:
                ck.err_rule(rule, it.key, f"{it.what}: {it.problem} (topic {show(d.name)}, {msg_type})")
                continue
            if it.n is None:
                continue
            _one_value_per_field(ck, rule, seen, it, it.n, "maximum")


#: The policies of a carried variable-length array or string for received
#: data longer than its maximum (rule 4.15, ``policy``).
POLICIES = ("truncate", "reject")


@dataclass
class _PolicyItem:
    """An entry of a topic's ``policy`` (rule 4.15): as :class:`_MaxItem`,
    with ``value`` the policy or ``value_problem`` why it is not one."""

    what: str
    key: YNode
    node: YNode
    target: BoundedTarget | None = None
    problem: str | None = None
    value: str | None = None
    value_problem: str | None = None


def policy_items(pnode: YMap, msg_type: str | None, registry: MsgRegistry, what: str) -> list[_PolicyItem]:
    """The entries of the ``policy`` mapping ``pnode`` of a topic of
    ``msg_type`` (``None``: unknown, the paths are not resolved)."""
    out = []
    for k, v in pnode.items:
        it = _PolicyItem(f"{what}.policy[{show(k.text)}]", k, v)
        if isinstance(v, YScalar) and v.kind == "str" and v.value in POLICIES:
            it.value = v.value
        elif not isinstance(v, YBad):
            hint = did_you_mean(v.value, POLICIES) if isinstance(v, YScalar) and v.kind == "str" else ""
            it.value_problem = f"must be truncate or reject, got {v.describe()}{hint}"
        if k.kind != "str":
            it.problem = f"a key of policy is a field path, got {k.describe()}"
        elif msg_type is not None:
            try:
                it.target = registry.walk_bounded(msg_type, k.value, "policy")
            except PathError as exc:
                it.problem = exc.args[0]
        out.append(it)
    return out


def check_policy(ck: Checker, decls: list[TopicDecl], registry: MsgRegistry) -> None:
    """Rule 4.15: a subscribed topic's ``policy: {<field path>: truncate |
    reject}`` names carried variable-length arrays or strings of its
    message; one field of a message type (one C struct in every topic of
    the type) gets one policy."""
    rule = "4.15"
    seen: dict[tuple[str, str], tuple[_PolicyItem, str]] = {}
    inner = _element_types(registry)
    for d in decls:
        pnode = d.node.get("policy")
        if pnode is None or isinstance(pnode, YBad):
            continue
        if not isinstance(pnode, YMap):
            ck.err_rule(rule, pnode, f"{d.what}.policy must be a mapping of field paths to truncate or reject "
                                     f"(e.g. {{ranges: reject}}), got {pnode.describe()}")
            continue
        if d.direction == PUBLISH:
            ck.err_rule(rule, pnode, f"{d.what}.policy: topic {show(d.name)} is published by the node; a policy "
                                     "says what a subscribed topic does with received data longer than its maximum")
            continue
        msg_type = d.msg_type if d.msg_type is not None and registry.raw(d.msg_type) is not None else None
        for it in policy_items(pnode, msg_type, registry, d.what):
            if it.value_problem is not None:
                ck.err_rule(rule, it.node, f"{it.what} {it.value_problem}")
            if msg_type is None:
                continue
            if it.problem is not None:
                ck.err_rule(rule, it.key, f"{it.what}: {it.problem} (topic {show(d.name)}, {msg_type})")
                continue
            if it.target.key not in registry.carry_bounded:
                owner, fname = it.target.key
                ck.err_rule(rule, it.key, f"{it.what}: {fname} of {owner} is not carried (no relation reads it), "
                                          f"so it has no policy (topic {show(d.name)})")
                continue
            if it.value is None:
                continue
            if it.value == "reject" and (it.target.in_element or it.target.owner in inner):
                owner, fname = it.target.key
                where = (f"{show(it.key.value)} is inside an element of a variable-length array" if it.target.in_element
                         else f"{fname} of {owner} is also inside the elements of {inner[owner]}")
                ck.err_rule(rule, it.key,
                            f"{it.what}: {where}: policy reject is refused there (the environment model's "
                            "Environment.too_long would test it in every element the node can hold, received or "
                            "not, the wrapper in the received ones only); use truncate, or reject on the array "
                            "itself")
                continue
            _one_value_per_field(ck, rule, seen, it, it.value, "policy")


def _one_value_per_field(ck: Checker, rule: str, seen: dict, it: _PolicyItem | _MaxItem,
                         value: str | int, noun: str) -> None:
    """One field of a message type (one C struct in every topic of the
    type) gets one value (rule 4.15): the entry ``it`` of a ``policy`` or
    ``max_length`` gives ``value`` (a ``noun``: policy, maximum) to the
    field ``it.target.key``; it is refused, with the position of the first
    entry, if an earlier one gave the field another value.  ``seen`` maps
    each field to its first entry and value (``it`` is added when it is
    the first)."""
    first = seen.get(it.target.key)
    if first is None:
        seen[it.target.key] = (it, value)
        return
    first_it, first_value = first
    if first_value != value:
        owner, fname = it.target.key
        ck.err_rule(rule, it.key,
                    f"{it.what}: {value} differs from the {noun} {first_value} given to the same field "
                    f"({fname} of {owner}) at line {first_it.key.line}, column {first_it.key.col} "
                    f"({first_it.what}); one C struct holds the field in every topic of type {owner}, "
                    f"so it has one {noun}")


def _element_types(registry: MsgRegistry) -> dict[str, str]:
    """The message types inside the elements of the carried
    variable-length arrays of messages (rule 4.15), each with the array
    it is in (``poses of nav_msgs/Path``): a string or sequence of these
    types is in every element of such an array."""
    out: dict[str, str] = {}
    for owner, fname in sorted(registry.carry_bounded):
        raw = registry.raw(owner)
        f = raw.field(fname) if raw is not None else None
        if f is None or f.card != "sequence" or f.base_kind != "msg":
            continue
        for t in registry.used_types([f.base]):
            out.setdefault(t.name, f"{fname} of {owner}")
    return out


def check_published_sequences(ck: Checker, out_rels: list[Rel], registry: MsgRegistry) -> None:
    """Rule 4.15, publish side: a published variable-length array or
    string whose elements output relations write also has its length
    written (``derived: length``), and so has every array a written leaf
    or length is inside (``poses`` for ``poses[0].pose.position.x`` and
    for the length of ``poses[0].header.frame_id``); a published string
    written by the controller has no constant (rule 4.14)."""
    # a refused relation on the field (its path, its derived) may have
    # meant the length: it is not reported again as a missing one
    lengths = {(r.topic.name, r.bounded.steps) for r in out_rels
               if (r.seq_kind == "length" or r.path is None) and r.topic is not None and r.bounded is not None}
    reported: set[tuple] = set()
    for r in out_rels:
        if r.topic is None or r.bounded is None or r.path is None:
            continue
        field_text = steps_text(r.bounded.steps)
        kind = "string" if r.bounded.is_string else "variable-length array"
        first = r.topic.constant_steps.get(r.bounded.steps)
        if first is not None:
            ck.err_rule("4.15", r.path_node,
                        f"{r.what}.field: the {kind} {show(field_text)} of topic {show(r.topic.name)} has a "
                        f"constant ({first[0]}, line {first[1]}); a published string comes from a constant or "
                        "from controller outputs, not both")
            r.ok = False
            continue
        fnode = r.node.get("field")
        along = registry.bounded_along(r.topic.msg_type, fnode.value) if isinstance(fnode, YScalar) else []
        if not along or along[-1].steps != r.bounded.steps:  # pragma: no cover - the same walk
            along = [r.bounded]
        need = along if r.seq_kind is None else along[:-1]
        for t in need:
            key = (r.topic.name, t.steps)
            if key in lengths or key in reported:
                continue
            reported.add(key)
            what = ("string" if t.is_string else "variable-length array of messages" if t.seq_of == "msg"
                    else "variable-length array of strings" if t.seq_of == "string" else "variable-length array")
            writes = "elements of" if t is along[-1] and r.seq_kind is None else "inside"
            ck.err_rule("4.15", r.path_node,
                        f"{r.what}.field: the controller writes {writes} the published {what} "
                        f"{show(t.shown)} of topic {show(r.topic.name)} but not its length: add "
                        f"{{output: <a uint32 output>, topic: {r.topic.name}, field: {_flow(t.shown)}, "
                        "derived: length} (the subscriber receives the first min(length, N) elements, N its "
                        "max_length)")
            r.ok = False
            break


def _flow(text: str) -> str:
    """A field path as a YAML flow mapping's value: quoted when it holds
    brackets."""
    return f'"{text}"' if "[" in text else text
