"""The system model: a YAML file naming a robot's nodes and how they connect.

Grammar (DESIGN.md section 10, rules 10.1 to 10.4)::

    system:
      name: guard_chain                  # a C identifier
    nodes:                               # 1 to MAX_NODES entries
      - model: guard/laser_guard.yaml    # a node model file (relative to this file)
        name: guard                      # optional: the ROS node name (default: the model's)
        namespace: /robot                # optional: default /
        remap: {cmd_vel: /guard/cmd_vel} # optional: from -> to (ROS names)
        controller: guard/controller     # optional: the controller folder (build)
    external:
      inputs:  [/scan, /teleop/cmd_vel]  # topics that enter from outside (sensors)
      outputs: [/base/wheels]            # topics that leave (actuators)
    shared: [/diagnostics]               # optional: topics several nodes may publish

Every problem is a :class:`~pyrosgen.errors.Diagnostic` with file, line,
column and rule; they are collected and raised together
(:class:`~pyrosgen.errors.InvalidNodeModel`, exit 1).  A node model with
problems is reported with its own file's positions.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from pyrosgen.errors import Diagnostic, InvalidNodeModel, show
from pyrosgen.frontend.model import NodeModel
from pyrosgen.frontend.names import identifier_problem, topic_name_problem
from pyrosgen.frontend.yamlsrc import YMap, YNode, YScalar, YSeq, parse_yaml, read_text
from pyrosgen.system.names import namespace_problem, node_name_problem, resolve

__all__ = ["MAX_NODES", "TARGETS", "SystemNode", "SystemModel", "load_system", "read_system"]

#: Most nodes a system file may name (rule 10.1).  A robot has 20 to 100;
#: the bound keeps a run's memory and the chains' enumeration bounded.
MAX_NODES = 256

#: Most remappings of one node, external topics, shared topics (rule 10.1).
MAX_ITEMS = 1024


@dataclass
class SystemNode:
    """One entry of ``nodes``: a node model and where it runs."""

    index: int
    model_path: Path
    model_node: YNode            #: the ``model`` value (for positions)
    entry: YMap
    name: str = ""               #: ROS node name (base)
    namespace: str = "/"
    remap: dict[str, str] = field(default_factory=dict)       #: resolved from -> resolved to
    remap_nodes: dict[str, YNode] = field(default_factory=dict)  #: resolved from -> its key node
    controller: Path | None = None
    model: NodeModel | None = None

    @property
    def full_name(self) -> str:
        """The node's resolved name: ``/robot/guard``."""
        return resolve(self.namespace, self.name)

    @property
    def folder(self) -> str:
        """Its folder in a system's output: the resolved name without its
        leading ``/``, ``/`` replaced by ``.`` (``robot.guard``)."""
        return self.full_name.lstrip("/").replace("/", ".")

    def graph_name(self, model_topic: str) -> str:
        """The name of the model's topic ``model_topic`` in the ROS graph:
        resolved in the namespace, then remapped."""
        r = resolve(self.namespace, model_topic)
        return self.remap.get(r, r)


@dataclass
class SystemModel:
    """A validated system file."""

    name: str
    source: Path
    nodes: list[SystemNode]
    inputs: dict[str, YNode]     #: external input topic -> its position
    outputs: dict[str, YNode]    #: external output topic -> its position
    shared: dict[str, YNode]
    #: the target every node is read, generated and built for (rule 4.17):
    #: ``"ros1"`` or ``"ros2"`` (``--ros2``)
    target: str = "ros1"


_TOP = {"system", "nodes", "external", "shared"}
_NODE_KEYS = {"model", "name", "namespace", "remap", "controller"}


class _Reader:
    def __init__(self, file: str, base: Path):
        self.file = file
        self.base = base
        self.diags: list[Diagnostic] = []

    def err(self, node: YNode | None, message: str, rule: str) -> None:
        line, col = (node.line, node.col) if node is not None else (None, None)
        self.diags.append(Diagnostic(self.file, line, col, message, rule=rule))

    def string(self, node: YNode | None, what: str, rule: str) -> str | None:
        if isinstance(node, YScalar) and node.kind == "str" and node.value != "":
            return str(node.value)
        if node is not None:
            got = node.describe() if hasattr(node, "describe") else "an invalid value"
            self.err(node, f"{what}: expected a non-empty string, got {got}", rule)
        return None

    def keys(self, m: YMap, allowed: set[str], required: set[str], what: str, rule: str) -> None:
        for k, _ in m.items:
            if k.text not in allowed:
                self.err(k, f"{what}: unknown key {show(k.text)} (allowed: {', '.join(sorted(allowed))})", rule)
        for r in sorted(required):
            if m.get(r) is None:
                self.err(YScalar(*m.owner_pos, None, "", "null"), f"{what}: missing key {show(r)}", rule)

    def topic_list(self, node: YNode | None, what: str) -> dict[str, YNode]:
        out: dict[str, YNode] = {}
        if node is None:
            return out
        if not isinstance(node, YSeq):
            self.err(node, f"{what}: expected a list of topic names, got {node.describe()}", "10.1")
            return out
        if len(node.items) > MAX_ITEMS:
            self.err(node, f"{what}: {len(node.items)} topics; at most {MAX_ITEMS}", "10.1")
            return out
        for i, item in enumerate(node.items):
            name = self.string(item, f"{what}[{i}]", "10.1")
            if name is None:
                continue
            problem = topic_name_problem(name)
            if problem is None and not name.startswith("/"):
                problem = "an external or shared topic is named by its global name (starting with '/')"
            if problem:
                self.err(item, f"{what}[{i}]: {show(name)} is not a ROS topic name: {problem}", "10.1")
            elif name in out:
                self.err(item, f"{what}[{i}]: {show(name)} is listed twice (first at line {out[name].line})", "10.1")
            else:
                out[name] = item
        return out


def read_system(path: str | Path) -> SystemModel:
    """Read and check the system file's own structure (rules 10.1 to
    10.4) without loading the node models."""
    path = Path(path)
    text = read_text(path, what="system file", rule="10.1")
    doc = parse_yaml(text, str(path))
    rd = _Reader(doc.file, path.parent)
    rd.diags.extend(doc.diagnostics)
    root = doc.root
    rd.keys(root, _TOP, {"system", "nodes", "external"}, "the system file", "10.1")

    name = "system"
    sysm = root.get("system")
    if isinstance(sysm, YMap):
        rd.keys(sysm, {"name"}, {"name"}, "system", "10.1")
        n = rd.string(sysm.get("name"), "system.name", "10.1")
        if n is not None:
            problem = identifier_problem(n)
            if problem:
                rd.err(sysm.get("name"), f"system.name: {show(n)} is not a valid name: {problem}", "10.1")
            else:
                name = n
    elif sysm is not None:
        rd.err(sysm, f"system: expected a mapping, got {sysm.describe()}", "10.1")

    nodes: list[SystemNode] = []
    nseq = root.get("nodes")
    if nseq is not None and not isinstance(nseq, YSeq):
        rd.err(nseq, f"nodes: expected a list, got {nseq.describe()}", "10.1")
    elif isinstance(nseq, YSeq):
        if not nseq.items:
            rd.err(nseq, "nodes: the list is empty; a system has at least one node", "10.1")
        if len(nseq.items) > MAX_NODES:
            rd.err(nseq, f"nodes: {len(nseq.items)} nodes; a system has at most {MAX_NODES} "
                         "(split it into several systems)", "10.1")
        else:
            for i, item in enumerate(nseq.items):
                sn = _read_node(rd, i, item)
                if sn is not None:
                    nodes.append(sn)

    inputs: dict[str, YNode] = {}
    outputs: dict[str, YNode] = {}
    ext = root.get("external")
    if isinstance(ext, YMap):
        rd.keys(ext, {"inputs", "outputs"}, set(), "external", "10.1")
        inputs = rd.topic_list(ext.get("inputs"), "external.inputs")
        outputs = rd.topic_list(ext.get("outputs"), "external.outputs")
        for t, node in outputs.items():
            if t in inputs:
                rd.err(node, f"external.outputs: {show(t)} is also an external input", "10.1")
    elif ext is not None:
        rd.err(ext, f"external: expected a mapping, got {ext.describe()}", "10.1")
    shared = rd.topic_list(root.get("shared"), "shared")

    # rule 10.3: a node listed twice, a node name used twice
    seen: dict[str, SystemNode] = {}
    for sn in nodes:
        if not sn.name:
            continue
        other = seen.get(sn.full_name)
        if other is None:
            seen[sn.full_name] = sn
            continue
        if other.model_path.resolve() == sn.model_path.resolve():
            msg = (f"nodes[{sn.index}]: node model {show(str(sn.model_node.value))} is listed twice in "
                   f"namespace {show(sn.namespace)} (first at line {other.entry.line}); give it another "
                   "name or namespace")
        else:
            msg = (f"nodes[{sn.index}]: node name {show(sn.full_name)} is used twice "
                   f"(first at line {other.entry.line})")
        rd.err(sn.entry, msg, "10.3")
    if rd.diags:
        raise InvalidNodeModel(sorted(rd.diags, key=_order))
    return SystemModel(name, path, nodes, inputs, outputs, shared)


def _order(d: Diagnostic):
    return (d.file, d.line or 0, d.col or 0)


def _read_node(rd: _Reader, i: int, item: YNode) -> SystemNode | None:
    what = f"nodes[{i}]"
    if not isinstance(item, YMap):
        rd.err(item, f"{what}: expected a mapping with a 'model', got {item.describe()}", "10.1")
        return None
    rd.keys(item, _NODE_KEYS, {"model"}, what, "10.1")
    mnode = item.get("model")
    mpath = rd.string(mnode, f"{what}.model", "10.2")
    if mpath is None:
        return None
    sn = SystemNode(index=i, model_path=rd.base / mpath, model_node=mnode, entry=item)
    if not sn.model_path.is_file():
        rd.err(mnode, f"{what}.model: node model file {show(mpath)} does not exist "
                      f"(looked for {show(str(sn.model_path))})", "10.2")
    nm = item.get("name")
    if nm is not None:
        n = rd.string(nm, f"{what}.name", "10.2")
        if n is not None:
            problem = node_name_problem(n)
            if problem:
                rd.err(nm, f"{what}.name: {show(n)} is not a ROS node name: {problem}", "10.2")
            else:
                sn.name = n
    ns = item.get("namespace")
    if ns is not None:
        v = rd.string(ns, f"{what}.namespace", "10.2")
        if v is not None:
            problem = namespace_problem(v)
            if problem:
                rd.err(ns, f"{what}.namespace: {show(v)} is not a ROS namespace: {problem}", "10.2")
            else:
                sn.namespace = v if v.startswith("/") else "/" + v
    ctl = item.get("controller")
    if ctl is not None:
        v = rd.string(ctl, f"{what}.controller", "10.2")
        if v is not None:
            sn.controller = rd.base / v
            if not sn.controller.is_dir():
                rd.err(ctl, f"{what}.controller: folder {show(v)} does not exist", "10.2")
    rm = item.get("remap")
    if rm is not None:
        _read_remap(rd, sn, rm, what)
    return sn


def _read_remap(rd: _Reader, sn: SystemNode, rm: YNode, what: str) -> None:
    if not isinstance(rm, YMap):
        rd.err(rm, f"{what}.remap: expected a mapping from topic names to topic names, got {rm.describe()}", "10.4")
        return
    if len(rm.items) > MAX_ITEMS:
        rd.err(rm, f"{what}.remap: {len(rm.items)} remappings; at most {MAX_ITEMS}", "10.4")
        return
    pairs: list[tuple[str, str, YNode, YNode]] = []
    for k, v in rm.items:
        src = k.text
        dst = rd.string(v, f"{what}.remap[{show(src)}]", "10.4")
        ok = True
        for side, nm, node in (("from", src, k), ("to", dst, v)):
            if nm is None:
                ok = False
                continue
            problem = topic_name_problem(nm)
            if problem:
                rd.err(node, f"{what}.remap: {side} name {show(nm)} is not a ROS topic name: {problem}", "10.4")
                ok = False
        if ok and dst is not None:
            pairs.append((resolve(sn.namespace, src), resolve(sn.namespace, dst), k, v))
    sources = {}
    for s, d, k, v in pairs:
        if s in sources:
            rd.err(k, f"{what}.remap: {show(s)} is remapped twice (first at line {sources[s][2].line})", "10.4")
            continue
        if s == d:
            rd.err(k, f"{what}.remap: {show(s)} is remapped to itself", "10.4")
            continue
        sources[s] = (s, d, k, v)
    for s, d, k, v in sources.values():
        if d in sources:
            kind = "a cycle" if _cycles(sources, s) else "a chain"
            rd.err(v, f"{what}.remap: {show(s)} -> {show(d)} -> {show(sources[d][1])} is {kind} of "
                      "remappings: ROS applies a remapping once, not in turn; remap each topic "
                      "straight to its final name", "10.4")
    sn.remap = {s: d for s, d, _, _ in sources.values()}
    sn.remap_nodes = {s: k for s, _, k, _ in sources.values()}


def _cycles(sources, start: str) -> bool:
    seen = set()
    cur = start
    while cur in sources and cur not in seen:
        seen.add(cur)
        cur = sources[cur][1]
    return cur == start


#: The targets a system is built for (rule 4.17; ``--ros2``).
TARGETS = ("ros1", "ros2")


def _node_loader(target: str):
    """The front end of ``target``: a function from a node model file to its
    model (ROS 2: read with ROS 2's message definitions, rule 4.17; a
    missing ROS 2 installation is exit 2 before any node is read)."""
    if target not in TARGETS:
        raise ValueError(f"unknown target {target!r}")
    if target == "ros2":
        from pyrosgen.ros2.env import find_ros2
        from pyrosgen.ros2.frontend import load_model_ros2

        inst = find_ros2()
        return lambda p: load_model_ros2(p, inst)
    from pyrosgen.frontend.validate import load_model

    return load_model


def load_system(path: str | Path, target: str = "ros1") -> SystemModel:
    """Read the system file and every node model it names (each with the
    node front end's checks, for ``target``: ``"ros1"`` or ``"ros2"``,
    rule 4.17); the cross-node checks are
    :func:`pyrosgen.system.checks.check_system`."""
    load_model = _node_loader(target)
    sysm = read_system(path)
    sysm.target = target
    diags: list[Diagnostic] = []
    rd = _Reader(str(sysm.source), sysm.source.parent)
    for sn in sysm.nodes:
        try:
            sn.model = load_model(sn.model_path)
        except InvalidNodeModel as exc:
            rd.err(sn.model_node, f"nodes[{sn.index}].model: node model {show(str(sn.model_node.value))} "
                                  f"is invalid{' for the target ros2' if target == 'ros2' else ''} "
                                  "(its problems follow)", "10.2")
            diags.extend(exc.diagnostics)
            continue
        if not sn.name:
            sn.name = sn.model.name
    if rd.diags or diags:
        raise InvalidNodeModel(sorted(rd.diags, key=_order) + diags)
    # names defaulted from the models: rule 10.3 again
    seen: dict[str, SystemNode] = {}
    for sn in sysm.nodes:
        other = seen.setdefault(sn.full_name, sn)
        if other is not sn:
            if other.model_path.resolve() == sn.model_path.resolve():
                msg = (f"nodes[{sn.index}]: node model {show(str(sn.model_node.value))} is listed twice in "
                       f"namespace {show(sn.namespace)} (first at line {other.entry.line}); give it another "
                       "name or namespace")
            else:
                msg = (f"nodes[{sn.index}]: node name {show(sn.full_name)} is used twice "
                       f"(first at line {other.entry.line}; the name defaults to the node model's)")
            rd.err(sn.entry, msg, "10.3")
    if rd.diags:
        raise InvalidNodeModel(rd.diags)
    return sysm
