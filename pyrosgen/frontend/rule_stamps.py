"""Rule 4.13 (stamps): ``stamp: now`` or ``stamp: {from: <subscribed
topic>}`` on a published topic whose message has a ``header.stamp`` of
the target's time type: ROS 1's ``time`` (``uint32 sec``, ``uint32
nsec``) or, for the target ros2 (rule 4.17), ``builtin_interfaces/Time``
(``int32 sec``, ``uint32 nanosec``).
"""

from __future__ import annotations

from pyrosgen.errors import show
from pyrosgen.frontend.checker import Checker, Rel, TopicDecl
from pyrosgen.frontend.msgload import MsgRegistry
from pyrosgen.frontend.names import did_you_mean
from pyrosgen.frontend.yamlsrc import YBad, YMap, YScalar


#: The field a stamped topic's message carries the time in (rule 4.13).
STAMP_FIELD = ("header", "stamp")


#: The time type of a stamp on the target ROS 2 (rule 4.17): ``int32 sec``,
#: ``uint32 nanosec`` (``NodeModel.time_msg``).
ROS2_TIME = "builtin_interfaces/Time"


def time_type(registry: MsgRegistry) -> str:
    """The type of a stamp: ROS 1's built-in ``time``, or ROS 2's
    ``builtin_interfaces/Time`` when the registry holds ROS 2's standard
    messages (the target ros2, rule 4.17)."""
    return ROS2_TIME if registry.standard is not None else "time"


def _has_stamp(registry: MsgRegistry, msg_type: str) -> bool:
    """Whether messages of ``msg_type`` have a ``header.stamp`` of the
    target's time type (:func:`time_type`)."""
    raw = registry.raw(msg_type)
    header = raw.field("header") if raw is not None else None
    hraw = registry.raw(header.base) if header is not None and header.card == "scalar" else None
    stamp = hraw.field("stamp") if hraw is not None else None
    return stamp is not None and stamp.card == "scalar" and stamp.base == time_type(registry)


def _stamp_source(ck: Checker, d: TopicDecl, snode: YMap, what: str,
                  decls: list[TopicDecl], registry: MsgRegistry) -> tuple[bool, str | None]:
    """``stamp: {from: <topic>}``: the named topic is subscribed by the node
    and its message has a ``header.stamp`` of type ``time``.  Returns
    whether it passed and the source topic's name."""
    rule = "4.13"
    ck.keys(snode, what, ("from",))
    fnode = snode.get("from")
    name = ck.string(fnode, f"{what}.from")
    if name is None:
        return False, None
    by_name = {e.name: e for e in decls if e.name is not None}
    src = by_name.get(name)
    if src is None:
        ck.err_rule(rule, fnode, f"{what}.from: {show(name)} is not a topic of the node"
                                 f"{did_you_mean(name, list(by_name))}")
        return False, None
    if src.direction is not None and src.direction != "subscribe":
        ck.err_rule(rule, fnode, f"{what}.from: topic {show(name)} is published by the node; "
                                 "a stamp is copied from a subscribed topic")
        return False, None
    if src.usable and src.type_ok and src.msg_type is not None and not _has_stamp(registry, src.msg_type):
        ck.err_rule(rule, fnode, f"{what}.from: message type {src.msg_type} of topic {show(name)} has no "
                                 f"header.stamp of type {time_type(registry)} to copy")
        return False, None
    return src.usable and src.type_ok, name


def check_stamps(ck: Checker, decls: list[TopicDecl], out_rels: list[Rel], registry: MsgRegistry) -> None:
    """Rule 4.13: ``stamp: now`` or ``stamp: {from: <subscribed topic>}``
    on a published topic whose message has a ``header.stamp`` of type
    ``time``, which no output relation writes.  Sets ``stamped`` (and
    ``stamp_from``) on the topics that pass."""
    rule = "4.13"
    for d in decls:
        snode = d.node.get("stamp")
        if snode is None or isinstance(snode, YBad):
            continue
        what = f"{d.what}.stamp"
        source = None
        if isinstance(snode, YMap):
            ok_src, source = _stamp_source(ck, d, snode, what, decls, registry)
            if not ok_src:
                continue
        elif not (isinstance(snode, YScalar) and snode.kind == "str" and snode.value == "now"):
            hint = (did_you_mean(snode.value, ("now",)) if isinstance(snode, YScalar) and snode.kind == "str" else "")
            ck.err_rule(rule, snode, f"{what} must be 'now' (the cycle's ROS time) or {{from: <topic>}} "
                                     f"(the stamp of a subscribed topic's newest message), got {snode.describe()}{hint}")
            continue
        if d.direction is not None and d.direction != "publish":
            ck.err_rule(rule, snode, f"{what}: topic {show(d.name)} is subscribed by the node; "
                                     "only a published message is stamped")
            continue
        if not (d.usable and d.type_ok and d.msg_type is not None):
            continue
        if not _has_stamp(registry, d.msg_type):
            ck.err_rule(rule, snode, f"{what}: message type {d.msg_type} of topic {show(d.name)} has no "
                                     f"header.stamp of type {time_type(registry)} to stamp")
            continue
        ok = True
        for r in out_rels:
            if r.topic is d and r.path is not None and tuple(r.path.steps[:2]) == STAMP_FIELD:
                ck.err_rule(rule, r.path_node, f"field {show(str(r.path))} of topic {show(d.name)} is written "
                                               "by the stamp; an output relation may not write it too")
                ok = False
        d.stamped = ok
        d.stamp_from = source if ok else None
