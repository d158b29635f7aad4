"""The checks across the nodes of a system (DESIGN.md rules 10.3 to 10.11)
and what they establish: the connections (links) and the chains.

A *link* is an output relation of a publisher and an input relation of a
subscriber on the same field of one graph topic (after namespaces and
remappings): the value the subscriber's controller receives is the value
the publisher's controller computed (``System.link_value``).  A *chain*
runs from an external input topic through nodes to an external output
topic; through each node it passes from a subscribed topic to a published
one (the controller is a function of all its inputs).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from pyrosgen.errors import Diagnostic, InvalidNodeModel, show
from pyrosgen.frontend.model import InputRelation, OutputRelation, Topic
from pyrosgen.system.model import SystemModel, SystemNode

__all__ = ["Link", "Hop", "Chain", "SystemGraph", "check_system", "MAX_CHAINS", "custom_message_packages",
           "msg_definition", "qos_problems"]

#: Most chains a certificate lists (the number of simple paths can grow
#: exponentially with the nodes; past it, the certificate says so).
MAX_CHAINS = 1000


@dataclass(frozen=True)
class Link:
    """Output relation ``out`` of ``pub`` feeds input relation ``inp`` of
    ``sub`` over graph topic ``topic``."""

    topic: str
    pub: SystemNode
    pub_topic: Topic
    out: OutputRelation
    sub: SystemNode
    sub_topic: Topic
    inp: InputRelation


@dataclass(frozen=True)
class Hop:
    """A chain's passage through ``node``: in on ``src`` (its input
    relations reading it), out on ``dst`` (its output relations writing it)."""

    node: SystemNode
    src: str
    dst: str
    inputs: tuple[InputRelation, ...]
    outputs: tuple[OutputRelation, ...]


@dataclass(frozen=True)
class Chain:
    """External input ``hops[0].src`` to external output ``hops[-1].dst``."""

    hops: tuple[Hop, ...]


@dataclass
class SystemGraph:
    """The topics of a checked system."""

    system: SystemModel
    publishers: dict[str, list[tuple[SystemNode, Topic]]] = field(default_factory=dict)
    subscribers: dict[str, list[tuple[SystemNode, Topic]]] = field(default_factory=dict)
    links: list[Link] = field(default_factory=list)
    chains: list[Chain] = field(default_factory=list)
    chains_truncated: bool = False
    warnings: list[Diagnostic] = field(default_factory=list)

    def topic_type(self, g: str) -> str | None:
        for _, t in self.publishers.get(g, []) + self.subscribers.get(g, []):
            return t.msg_type
        return None


def _where(sn: SystemNode, t: Topic) -> str:
    src = sn.model.source if sn.model is not None else sn.model_path
    return f"{src}:{t.pos.line}" if t.pos.line else str(src)


def check_system(sysm: SystemModel) -> SystemGraph:
    """Run rules 10.3 to 10.11 (10.11: the target ROS 2) on a loaded system; raise
    :class:`InvalidNodeModel` with every problem, else return the graph."""
    file = str(sysm.source)
    diags: list[Diagnostic] = []

    def err(node, message: str, rule: str) -> None:
        diags.append(Diagnostic(file, node.line, node.col, message, rule=rule))

    gr = SystemGraph(sysm)
    # rule 10.3: the system's proof loads each node's module by its node
    # name, so two different node models may not share one
    by_name: dict[str, SystemNode] = {}
    for sn in sysm.nodes:
        other = by_name.setdefault(sn.model.name, sn)
        if other is not sn and Path(other.model.source).resolve() != Path(sn.model.source).resolve():
            err(sn.model_node, f"nodes[{sn.index}]: node models {show(str(other.model_node.value))} and "
                               f"{show(str(sn.model_node.value))} both name their node {show(sn.model.name)}; the "
                               "system's proof loads each node by that name: rename one (node.name)", "10.3")
    for sn in sysm.nodes:
        m = sn.model
        assert m is not None
        # rule 10.4: every remapping renames a topic of the node
        names = {sn.graph_name(t.name): t for t in m.topics}
        from pyrosgen.system.names import resolve
        resolved = {resolve(sn.namespace, t.name) for t in m.topics}
        for src, knode in sn.remap_nodes.items():
            if src not in resolved:
                err(knode, f"nodes[{sn.index}].remap: {show(src)} is not a topic of node {show(m.name)} "
                           f"(its topics, resolved: {', '.join(sorted(resolved))})", "10.4")
        # rule 10.3: a node's topics stay distinct after remapping
        seen: dict[str, Topic] = {}
        for t in m.topics:
            g = sn.graph_name(t.name)
            if g in seen:
                err(sn.model_node, f"nodes[{sn.index}]: topics {show(seen[g].name)} and {show(t.name)} of node "
                                   f"{show(m.name)} are both {show(g)} after namespace and remapping", "10.3")
                continue
            seen[g] = t
            (gr.publishers if t.is_published else gr.subscribers).setdefault(g, []).append((sn, t))
        del names

    # rule 10.10: one definition of each custom message across the nodes
    _check_custom_messages(sysm, err)

    # rule 10.5: every subscription is fed
    for g, subs in sorted(gr.subscribers.items()):
        if g in gr.publishers:
            if g in sysm.inputs:
                pn, pt = gr.publishers[g][0]
                err(sysm.inputs[g], f"external.inputs: {show(g)} is published by node {show(pn.full_name)} "
                                    f"({_where(pn, pt)}); an external input comes from outside the system",
                    "10.5")
            continue
        if g in sysm.inputs:
            continue
        for sn, t in subs:
            err(sn.model_node, f"nodes[{sn.index}]: node {show(sn.full_name)} subscribes to {show(g)} "
                               f"({_where(sn, t)}), which no node publishes and which is not an external "
                               "input", "10.5")
    for g, node in sysm.outputs.items():
        if g not in gr.publishers:
            err(node, f"external.outputs: no node publishes {show(g)}", "10.5")
    for g, node in sysm.inputs.items():
        if g not in gr.subscribers and g not in gr.publishers:
            err(node, f"external.inputs: no node subscribes to {show(g)}", "10.5")
    for g, node in sysm.shared.items():
        if len(gr.publishers.get(g, [])) < 2:
            err(node, f"shared: {show(g)} is published by {len(gr.publishers.get(g, []))} node(s); "
                      "'shared' is for a topic several nodes publish", "10.6")

    # rule 10.6: one publisher per topic unless shared
    for g, pubs in sorted(gr.publishers.items()):
        if len(pubs) > 1 and g not in sysm.shared:
            first = pubs[0][0]
            for sn, t in pubs[1:]:
                err(sn.model_node, f"nodes[{sn.index}]: {show(g)} is published by node {show(sn.full_name)} "
                                   f"({_where(sn, t)}) and by node {show(first.full_name)}; declare it under "
                                   "'shared' if several publishers are intended", "10.6")

    # rules 10.7 to 10.9, per publisher-subscriber pair
    for g, subs in sorted(gr.subscribers.items()):
        for pn, pt in gr.publishers.get(g, []):
            for sn, st in subs:
                if pt.msg_type != st.msg_type:
                    err(sn.model_node, f"nodes[{sn.index}]: node {show(sn.full_name)} subscribes to {show(g)} "
                                       f"as {st.msg_type} ({_where(sn, st)}) but node {show(pn.full_name)} "
                                       f"publishes it as {pt.msg_type} ({_where(pn, pt)})", "10.7")
                    continue
                _check_leaves(gr, g, pn, pt, sn, st, err)
                if sysm.target == "ros2":
                    _check_qos(g, pn, pt, sn, st, err)
                if st.timeout_ms is not None and st.timeout_ms < pn.model.period_ms:
                    err(sn.model_node, f"nodes[{sn.index}]: the timeout of {show(g)} in node {show(sn.full_name)} "
                                       f"({st.timeout_ms} ms, {_where(sn, st)}) is shorter than the period of its "
                                       f"publisher {show(pn.full_name)} ({pn.model.period_ms} ms): the input "
                                       "would be stale between any two messages", "10.9")
    if diags:
        raise InvalidNodeModel(sorted(diags, key=lambda d: (d.line or 0, d.col or 0, d.message)))
    gr.chains, gr.chains_truncated = _chains(gr)
    return gr


def _written(pn: SystemNode, pt: Topic) -> tuple[set[tuple], list[tuple]]:
    """The leaves of ``pt`` that ``pn`` writes: those of its output
    relations (exact), and the prefixes it fills (the stamp, rule 4.13,
    and constant strings, rule 4.14)."""
    m = pn.model
    exact = {tuple(o.path.steps) for o in m.output_relations if o.topic.name == pt.name}
    prefixes: list[tuple] = []
    if pt.stamped:
        prefixes.append(("header", "stamp"))
    for s in pt.strings:
        prefixes.append(tuple(s.path))
    return exact, prefixes


def _check_leaves(gr: SystemGraph, g: str, pn: SystemNode, pt: Topic, sn: SystemNode, st: Topic, err) -> None:
    """Rule 10.8: every leaf a subscriber's input relation reads is one the
    publisher writes; each such pair with an output relation is a link."""
    exact, prefixes = _written(pn, pt)
    outs = {tuple(o.path.steps): o for o in pn.model.output_relations if o.topic.name == pt.name}
    for r in sn.model.input_relations:
        if r.topic.name != st.name:
            continue
        steps = tuple(r.path.steps)
        o = outs.get(steps)
        if o is not None:
            gr.links.append(Link(g, pn, pt, o, sn, st, r))
            continue
        if steps in exact or any(steps[:len(p)] == p for p in prefixes):
            continue
        err(sn.model_node, f"nodes[{sn.index}]: input {show(r.input_target)} of node {show(sn.full_name)} reads "
                           f"{show(r.field_text)} of {show(g)} ({sn.model.source}:{r.pos.line}), which its publisher "
                           f"{show(pn.full_name)} never writes ({_where(pn, pt)}: it is always 0); relate an output "
                           "to it or read another field", "10.8")


def qos_problems(pub_qos, sub_qos) -> list[str]:
    """Why a subscription of QoS ``sub_qos`` receives nothing from a
    publisher of QoS ``pub_qos`` (rule 10.11), as DDS matches a writer's
    offered QoS with a reader's requested QoS (rmw_fastrtps: Fast DDS's
    request/offered check; ``rmw_qos_profile_check_compatible``): a
    ``reliable`` reader needs a ``reliable`` writer, a ``transient_local``
    reader a ``transient_local`` writer; every other combination
    matches (a ``best_effort`` reader of a ``reliable`` writer, a
    ``volatile`` reader of a ``transient_local`` one).  Empty when they
    match."""
    out = []
    if sub_qos.reliability == "reliable" and pub_qos.reliability == "best_effort":
        out.append("a reliable subscription does not match a best_effort publisher (DDS delivers nothing): make "
                   "the publisher reliable or the subscription best_effort")
    if sub_qos.durability == "transient_local" and pub_qos.durability == "volatile":
        out.append("a transient_local subscription does not match a volatile publisher (DDS delivers nothing): "
                   "make the publisher transient_local or the subscription volatile")
    return out


def _check_qos(g: str, pn: SystemNode, pt: Topic, sn: SystemNode, st: Topic, err) -> None:
    """Rule 10.11 (target ROS 2): the subscription's QoS and its
    publisher's are compatible (:func:`qos_problems`)."""
    for why in qos_problems(pt.qos, st.qos):
        err(sn.model_node, f"nodes[{sn.index}]: node {show(sn.full_name)} subscribes to {show(g)} with QoS "
                           f"{st.qos.reliability}, {st.qos.durability} ({_where(sn, st)}) but node "
                           f"{show(pn.full_name)} publishes it with {pt.qos.reliability}, {pt.qos.durability} "
                           f"({_where(pn, pt)}): {why}", "10.11")


def _chains(gr: SystemGraph) -> tuple[list[Chain], bool]:
    """Every chain from an external input to an external output (simple:
    no node twice), at most :data:`MAX_CHAINS`."""
    sysm = gr.system
    out: list[Chain] = []
    truncated = False

    def hops_from(g: str):
        for sn, st in gr.subscribers.get(g, []):
            ins = tuple(r for r in sn.model.input_relations if r.topic.name == st.name)
            for pt in sn.model.published:
                dst = sn.graph_name(pt.name)
                outs = tuple(o for o in sn.model.output_relations if o.topic.name == pt.name)
                yield Hop(sn, g, dst, ins, outs)

    def walk(g: str, path: list[Hop], visited: set[str]) -> None:
        nonlocal truncated
        for hop in hops_from(g):
            if len(out) >= MAX_CHAINS:
                truncated = True
                return
            if hop.node.full_name in visited:
                continue
            p = path + [hop]
            if hop.dst in sysm.outputs:
                out.append(Chain(tuple(p)))
            walk(hop.dst, p, visited | {hop.node.full_name})

    for g in sysm.inputs:
        walk(g, [], set())
    return out, truncated


def msg_definition(text: str) -> tuple[str, ...]:
    """What a ``.msg`` file defines, as ``genmsg`` reads it: its lines
    without comments and blank lines, the blanks of each line collapsed
    (a string constant's value, after ``=``, kept as written)."""
    out = []
    for line in text.splitlines():
        head, eq, value = line.partition("=")
        if eq and head.split() and head.split()[0] == "string":
            out.append(" ".join(head.split()) + "=" + value.strip())
            continue
        line = line.split("#", 1)[0]
        if line.strip():
            out.append(" ".join(line.replace("=", " = ").split()))
    return tuple(out)


def custom_message_packages(sysm: SystemModel) -> dict[str, dict[str, tuple[SystemNode, Path]]]:
    """The custom message packages of the system's nodes (those of their
    ``msg_paths``, :func:`pyrosgen.ros.wrapper.custom_message_packages`):
    package -> ``.msg`` file name -> (the first node whose package has it,
    the file).  The workspace of ``system build`` holds one catkin package
    per name, with every file (rule 10.10 makes them agree)."""
    from pyrosgen.ros.wrapper import custom_message_packages as node_packages

    out: dict[str, dict[str, tuple[SystemNode, Path]]] = {}
    for sn in sysm.nodes:
        for pkg, folder in sorted(node_packages(sn.model).items()):
            files = out.setdefault(pkg, {})
            for f in sorted(Path(folder).glob("*.msg")):
                files.setdefault(f.name, (sn, f))
    return out


def _check_custom_messages(sysm: SystemModel, err) -> None:
    """Rule 10.10: a catkin workspace holds one package per name, so two
    nodes whose ``msg_paths`` define the same ``pkg/Type`` define it alike
    (the same fields and constants; comments and blanks aside), and no
    custom message package has the name of a node's package."""
    from pyrosgen.ros.wrapper import custom_message_packages as node_packages

    first: dict[str, tuple[SystemNode, Path, tuple[str, ...]]] = {}
    node_pkgs = {sn.model.name for sn in sysm.nodes}
    for sn in sysm.nodes:
        pkgs = node_packages(sn.model)
        for pkg, folder in sorted(pkgs.items()):
            if pkg in node_pkgs:
                err(sn.model_node, f"nodes[{sn.index}]: the custom message package {show(pkg)} of node "
                                   f"{show(sn.full_name)} ({folder}) has the name of a node's package; a catkin "
                                   "workspace holds one package of each name: rename one", "10.10")
            for f in sorted(Path(folder).glob("*.msg")):
                try:
                    text = f.read_text(encoding="utf-8", errors="replace")
                except OSError as exc:
                    err(sn.model_node, f"nodes[{sn.index}]: cannot read {f}: {exc.strerror or exc}", "10.10")
                    continue
                key = f"{pkg}/{f.stem}"
                seen = first.setdefault(key, (sn, f, msg_definition(text)))
                if seen[0] is not sn and seen[2] != msg_definition(text):
                    err(sn.model_node, f"nodes[{sn.index}]: node {show(sn.full_name)} defines the message "
                                       f"{show(key)} ({f}) otherwise than node {show(seen[0].full_name)} "
                                       f"({seen[1]}); the system's workspace holds one package {show(pkg)}: give "
                                       "both nodes the same definition", "10.10")
