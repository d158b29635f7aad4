"""Rules 4.4 (topics) and 4.5 (message types): each topic's name, direction,
queue size and message type, and the limits on what a message and the
node carry (scalar leaves, fields per struct).
"""

from __future__ import annotations

from pyrosgen.errors import show
from pyrosgen.frontend.checker import Checker, TopicDecl
from pyrosgen.frontend.model import PUBLISH, SUBSCRIBE
from pyrosgen.frontend.msgload import MsgRegistry
from pyrosgen.frontend import msgmodel
from pyrosgen.frontend.msgmodel import MAX_LEAVES, MAX_TOTAL_LEAVES, leaf_count, widest_struct
from pyrosgen.frontend.names import did_you_mean, topic_name_problem
from pyrosgen.frontend.yamlsrc import YBad, YNode, YSeq


#: Largest accepted subscriber/publisher queue.
MAX_QUEUE_SIZE = 10_000


def topics_section(ck: Checker, node: YNode | None, registry: MsgRegistry) -> list[TopicDecl]:
    """The topic declarations written at ``node`` (rules 4.4, 4.5), each as
    far as it checks; a topic declared twice is reported and left out."""
    if node is None or isinstance(node, YBad):
        return []
    if not isinstance(node, YSeq):
        ck.err(node, f"topics must be a list of topic declarations, got {node.describe()}")
        return []
    ck.topics_listed = True
    if not node.items:
        ck.err(node, "topics must declare at least one topic")
    decls: list[TopicDecl] = []
    by_name: dict[str, TopicDecl] = {}
    total_leaves, total_reported = 0, False
    for i, item in enumerate(node.items):
        what = f"topics[{i}]"
        m = ck.mapping(item, what)
        if m is None:
            continue
        ck.keys(m, what, ("name", "direction", "type", "queue_size"),
                ("timeout_ms", "on_timeout", "stamp", "frame_id", "strings", "max_length", "policy", "qos"))
        name_node = m.get("name")
        name = ck.string(name_node, f"{what}.name")
        usable = name is not None
        if name is not None:
            problem = topic_name_problem(name)
            if problem:
                ck.err_rule("4.4", name_node, f"{what}.name: topic name {show(name)} is not a valid ROS topic name: {problem}")
                usable = False
            if name in by_name:
                first = by_name[name]
                ck.err_rule("4.4", name_node, f"{what}.name: topic {show(name)} is declared twice (first at line {first.name_node.line})")
                continue
        d = TopicDecl(name if name is not None else f"<topics[{i}]>", m, name_node or m, what)
        if name is not None:
            by_name[name] = d
        decls.append(d)
        dnode = m.get("direction")
        direction = ck.string(dnode, f"{what}.direction")
        if direction is not None and direction not in (SUBSCRIBE, PUBLISH):
            ck.err(
                dnode,
                f"{what}.direction must be 'subscribe' or 'publish', got {show(direction)}"
                f"{did_you_mean(direction, (SUBSCRIBE, PUBLISH))}",
            )
            direction = None
        d.direction = direction
        d.queue_size = ck.integer(m.get("queue_size"), f"{what}.queue_size", 1, MAX_QUEUE_SIZE)
        tnode = m.get("type")
        d.type_node = tnode
        n = _message_type(ck, d, ck.string(tnode, f"{what}.type"), registry)
        type_ok = n is not None
        if type_ok:
            total_leaves += n
            if total_leaves > MAX_TOTAL_LEAVES and not total_reported:
                total_reported = True
                ck.err_rule(
                    "4.5",
                    tnode,
                    f"{what}.type: the topics up to this one carry {total_leaves} scalar leaves "
                    f"in all; a node carries at most {MAX_TOTAL_LEAVES}",
                )
        d.type_ok = type_ok
        d.usable = usable and type_ok and direction is not None and d.queue_size is not None
    return decls


def _message_type(ck: Checker, d: TopicDecl, t: str | None, registry: MsgRegistry) -> int | None:
    """Topic ``d``'s message type ``t`` as written (rule 4.5): a known type
    that carries at least one field, within the limits of one message.
    Sets ``d.msg_type``; returns its number of scalar leaves, or ``None``
    when it is refused (reported)."""
    what, tnode = d.what, d.type_node
    if t is not None:
        problem = registry.check_type_name(t)
        if t in registry.failed:
            pass  # its .msg file could not be read: reported there
        elif problem:
            ck.err_rule("4.5", tnode, f"{what}.type: {problem}")
        else:
            d.msg_type = t
            carried = registry.carried(t)
            if registry.is_broken(t):
                pass  # reported in the .msg file
            elif carried is None:
                ck.err_rule(
                    "4.5",
                    tnode,
                    f"{what}.type: message type {t} carries no field "
                    "(strings and variable-length arrays are not carried by the glue)",
                )
            else:
                messages = registry.messages()
                n = leaf_count(carried, messages)
                wide, width = widest_struct(carried, messages)
                if n > MAX_LEAVES:
                    ck.err_rule(
                        "4.5",
                        tnode,
                        f"{what}.type: message type {t} has {n} scalar leaves; "
                        f"the glue carries at most {MAX_LEAVES} per message"
                        + (" (lower the max_length of its variable-length arrays and strings: each "
                           "carries its maximum, every element of an array of messages or strings "
                           "all of its element's leaves)" if _has_bounded(carried, registry) else ""),
                    )
                # read from msgmodel when used: bench/limits.py lifts it for one run
                elif width > msgmodel.MAX_STRUCT_FIELDS:
                    ck.err_rule(
                        "4.5",
                        tnode,
                        f"{what}.type: message type {wide}{' (in ' + t + ')' if wide != t else ''} "
                        f"has {width} carried fields; at most {msgmodel.MAX_STRUCT_FIELDS} per message "
                        "definition (nest them in sub-messages, or use an array)",
                    )
                else:
                    return n
    return None


def _has_bounded(t, registry: MsgRegistry) -> bool:
    """Whether carried type ``t`` holds a variable-length array or a string."""
    return any(m.is_bounded for m in registry.used_types([t.name]))
