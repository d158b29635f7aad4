"""Rule 4.9 (names), for the C names the generators derive: each is a usable
identifier of at most :data:`~pyrosgen.frontend.names.MAX_NAME_LEN`
characters, and no two coincide (nor with the glue's own names).
"""

from __future__ import annotations

from pyrosgen.errors import show
from pyrosgen.frontend.checker import Checker, TopicDecl
from pyrosgen.frontend.model import SUBSCRIBE, Topic
from pyrosgen.frontend.msgload import MsgRegistry
from pyrosgen.frontend.names import MAX_NAME_LEN, identifier_problem, topic_c_name, topic_name_problem
from pyrosgen.frontend.yamlsrc import YMap


#: Names the generated C defines or calls whatever the model says.
FIXED_C_NAMES = (
    "input_glue",
    "loop",
    "main",
    "ros_init",
    "ros_ok",
    "ros_spinOnce",
    "ros_rate_sleep",
    "ros_now",
    "ros_time_sec",
    "ros_time_nsec",
    # temporaries: loop's answer of ros_ok; input_glue's cycle time and a
    # timed topic's age (rule 4.12)
    "_ok",
    "_now",
    "_age",
)


#: Local names of the generated functions (parameters of the callbacks and
#: output glues).  Coq's ``generate`` requires every global name to differ
#: from every local one, so that no local hides a global.  (The temporaries
#: ``_t_<type>``, like those of :data:`FIXED_C_NAMES`, start with '_',
#: which no global may.)
LOCAL_C_NAMES = ("msg", "command")


def check_c_names(ck: Checker, decls, ctrl_name, cm, uvar, yvar, registry: MsgRegistry,
                  timed: set[str] = frozenset()) -> None:
    """Check that every C name the generators derive is a usable identifier
    of at most :data:`MAX_NAME_LEN` characters and that no two coincide
    (``timed``: the names of the timed topics, whose glue has three more
    globals, rule 4.12)."""
    seen: dict[str, str] = {}

    def claim(name: str, origin: str, where, rule: str = "4.9") -> None:
        problem = identifier_problem(name, global_scope=True)
        if problem:
            ck.err_rule(rule, where, f"the C name {show(name)} derived from {origin} cannot be used: {problem}")
            return
        if name in seen:
            ck.err_rule(rule, where, f"the C name {show(name)} derived from {origin} collides with the one derived from {seen[name]}")
            return
        seen[name] = origin

    for n in FIXED_C_NAMES:
        seen[n] = "the generated glue (a temporary)" if n.startswith("_") else "the generated glue"
    for n in LOCAL_C_NAMES:
        seen[n] = "the generated glue (a parameter name)"
    if ctrl_name is not None:
        where = cm.get("name") if cm is not None else None
        for n in (f"{ctrl_name}_step", f"{ctrl_name}_initialize", f"ExtU_{ctrl_name}_T", f"ExtY_{ctrl_name}_T"):
            claim(n, f"controller {show(ctrl_name)}", where)
    if cm is not None:
        for var, key in ((uvar, "inputs"), (yvar, "outputs")):
            sub = cm.get(key)
            if var is not None and isinstance(sub, YMap):
                claim(var, f"controller.{key}.name", sub.get("name"))
    if ctrl_name is not None and cm is not None and cm.get("blocks") is not None:
        # the state global and struct of a diagram's C (rule 4.11)
        for n in (f"{ctrl_name}_DW", f"DW_{ctrl_name}_T"):
            claim(n, f"the block diagram of controller {show(ctrl_name)} (its state)", cm.key_node("blocks"),
                  rule="4.11")

    c_names: dict[str, TopicDecl] = {}
    for d in decls:
        if d.name.startswith("<") or topic_name_problem(d.name):
            continue
        c = topic_c_name(d.name)
        if c in c_names:
            ck.err_rule(
                "4.9",
                d.name_node,
                f"topics {show(c_names[c].name)} (line {c_names[c].name_node.line}) and "
                f"{show(d.name)} have the same C name {show(c)}",
            )
            continue
        c_names[c] = d
        problem = identifier_problem(c, global_scope=True)
        if problem and not problem.startswith("it is longer"):
            ck.err_rule("4.9", d.name_node, f"topic {show(d.name)}: its C name {show(c)} cannot be used: {problem}")
            continue
        longest = max(
            (f"ros_subscribe_{c}", f"ros_advertise_{c}", f"output_glue_{c}", f"{c}_callback"),
            key=len,
        )
        if len(longest) > MAX_NAME_LEN:
            ck.err_rule(
                "4.9",
                d.name_node,
                f"topic {show(d.name)}: the derived C name {show(longest)} is longer than "
                f"{MAX_NAME_LEN} characters; use a shorter topic name",
            )
            continue
        t = Topic(d.name, c, d.direction or SUBSCRIBE, "", 1)
        for n in t.derived_names():
            claim(n, f"topic {show(d.name)}", d.name_node)
        if d.name in timed:
            for n in t.timed_names():
                claim(n, f"topic {show(d.name)} (its receipt time and flags, rule 4.12)", d.name_node)

    used = registry.used_types(d.msg_type for d in decls if d.type_ok and d.msg_type)
    type_nodes = {}
    for d in decls:
        if d.type_ok and d.msg_type and d.msg_type not in type_nodes:
            type_nodes[d.msg_type] = d.type_node
    contained = {tname: {m.name for m in registry.used_types([tname])} for tname in type_nodes}
    for mt in used:
        # Report at the first topic whose type uses it.
        where = None
        for tname, tnode in type_nodes.items():
            if mt.name == tname or mt.name in contained[tname]:
                where = tnode
                break
        claim(mt.c_name, f"message type {mt.name}", where)
