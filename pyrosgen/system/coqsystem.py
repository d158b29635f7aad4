"""The per-system Coq file (``coq/templates/system.v.j2``) and its proof:
each link of the system as an instance of ``System.system_link``, proved
from the two nodes' compiled modules (their ``<node>_ddc``), then
``Print Assumptions`` and ``coqchk`` (DESIGN.md section 10)."""

from __future__ import annotations

import shutil
from pathlib import Path

from pyrosgen.errors import ToolFailure
from pyrosgen.frontend.model import InputRelation, OutputRelation, Topic
from pyrosgen.frontend.msgmodel import msg_c_name
from pyrosgen.proof.coqmodel import coq_comment, coq_ident, coq_nat, coq_path, coq_ros_name, coq_string, coq_z
from pyrosgen.render import render, source_label

__all__ = ["SYSTEM_TEMPLATE", "system_v_name", "system_theorem", "render_system_file", "prove_system", "chain_links",
           "chain_stages", "chain_theorems", "chain_path"]

SYSTEM_TEMPLATE = "coq/templates/system.v.j2"


def system_v_name(system: str) -> str:
    return f"{system}_system.v"


def system_theorem(system: str) -> str:
    return f"{system}_system"


def _topic(t: Topic) -> str:
    direction = "Subscribe" if t.is_subscribed else "Publish"
    msg = t.msg_type
    return (f"mktopic {coq_ros_name(t.name)} {coq_ident(t.c_name, 'topic C name')} {coq_string(msg)} "
            f"{direction} {coq_ident(msg_c_name(msg), 'message struct name')} {coq_nat(t.queue_size)}")


def _elem(idx: int | None) -> str:
    return "[]" if idx is None else f"[PIndex {coq_z(idx)}]"


def _outrel(o: OutputRelation) -> str:
    return (f"mkoutrel_at {coq_ident(o.output_field, 'controller output')} {_elem(o.output_index)} "
            f"{coq_ident(o.topic.c_name, 'topic C name')} {coq_path(o.path)}")


def _inrel(r: InputRelation) -> str:
    return (f"mkinrel_at {coq_ident(r.topic.c_name, 'topic C name')} {coq_path(r.path)} "
            f"{coq_ident(r.input_field, 'controller input')} {_elem(r.input_index)}")


def render_system_file(sysm, graph) -> str:
    """The per-system ``.v`` of a checked system."""
    modules = sorted({sn.model.name for sn in sysm.nodes})
    for m in modules:
        coq_ident(m, "node name")
    gindex = {}
    graphs = []
    for i, sn in enumerate(sysm.nodes):
        gindex[sn.full_name] = i
        pairs = [(coq_ros_name(t.name), coq_ros_name(sn.graph_name(t.name))) for t in sn.model.topics]
        graphs.append((i, coq_comment(f"{sn.full_name}: {sn.model.name} in namespace {sn.namespace}"), pairs))
    links = []
    for k, ln in enumerate(graph.links, 1):
        comment = coq_comment(f"{ln.topic}: {ln.pub.full_name} {ln.out.output_source} -> {ln.out.field_text}; "
                              f"{ln.sub.full_name} {ln.inp.field_text} -> {ln.inp.input_target}")
        links.append((k, comment, ln.pub.model.name, gindex[ln.pub.full_name], _topic(ln.pub_topic), _outrel(ln.out),
                      ln.sub.model.name, gindex[ln.sub.full_name], _topic(ln.sub_topic), _inrel(ln.inp)))
    cnodes = [(i, sn.model.name) for i, sn in enumerate(sysm.nodes)]
    chains = []
    for c, (ch, stages) in enumerate(zip(graph.chains, chain_stages(graph)), 1):
        path = " -> ".join([ch.hops[0].src] + [f"{h.node.full_name} -> {h.dst}" for h in ch.hops])
        nodes = [(gindex[h.node.full_name], h.node.model.name) for h in ch.hops]
        last = ch.hops[-1].node.model.name
        outs = [(q, last, _topic(o.topic), _outrel(o)) for q, o in enumerate(ch.hops[-1].outputs, 1)]
        chains.append((c, coq_comment(path), nodes, stages, outs, chain_path(len(nodes), stages, outs)))
    system = coq_ident(sysm.name, "system name")[1:-1]
    claims = []
    for c, _, _, _, outs, cpath in chains:
        claims.append((f"{system}_chain_{c}", f"chain_holds chain_{c}_nodes chain_{c}_links chain_{c}_outs"))
        if cpath is not None:
            claims.append((f"{system}_chain_{c}_composed",
                           f"chain_composed chain_{c}_nodes (mkcout ({outs[0][2]}) ({outs[0][3]})) "
                           f"(path_pick chain_{c}_links chain_{c}_path)"))
    return render("system.v.j2", template=SYSTEM_TEMPLATE, source=source_label(sysm.source.name),
                  system=system, modules=modules, graphs=graphs, links=links, cnodes=cnodes, chains=chains,
                  claims=claims, target="Ros2" if sysm.target == "ros2" else "Ros1")


def chain_path(n: int, stages: list[tuple[int, int]], outs: list) -> list[int] | None:
    """The positions, in a chain's links ``stages``, of the first link of
    each of its ``n - 1`` pairs of nodes; None when a pair has no link or
    the chain has no output relation (nothing to compose)."""
    if not outs:
        return None
    path = []
    for pos in range(n - 1):
        q = next((q for q, (p, _) in enumerate(stages) if p == pos), None)
        if q is None:
            return None
        path.append(q)
    return path


def chain_links(graph) -> list[list[int]]:
    """For each chain of ``graph``, the numbers (from 1) of the links it
    passes: those from the node of one hop to the node of the next on the
    topic between them."""
    out = []
    for ch in graph.chains:
        ks = []
        for h, nxt in zip(ch.hops, ch.hops[1:]):
            for k, ln in enumerate(graph.links, 1):
                if ln.topic == h.dst and ln.pub is h.node and ln.sub is nxt.node:
                    ks.append(k)
        out.append(ks)
    return out


def chain_stages(graph) -> list[list[tuple[int, int]]]:
    """For each chain of ``graph``, its links as ``(pos, k)``: link number
    ``k`` (from 1) joins the chain's node ``pos`` (from 0) to node
    ``pos + 1``."""
    out = []
    for ch in graph.chains:
        st = []
        for pos, (h, nxt) in enumerate(zip(ch.hops, ch.hops[1:])):
            for k, ln in enumerate(graph.links, 1):
                if ln.topic == h.dst and ln.pub is h.node and ln.sub is nxt.node:
                    st.append((pos, k))
        out.append(st)
    return out


def chain_theorems(system: str, graph) -> list[str]:
    """The chain theorems of the system's file, in order: each chain's, then
    its composition where it has one."""
    out = []
    for c, (ch, stages) in enumerate(zip(graph.chains, chain_stages(graph)), 1):
        out.append(f"{system}_chain_{c}")
        if chain_path(len(ch.hops), stages, ch.hops[-1].outputs) is not None:
            out.append(f"{system}_chain_{c}_composed")
    return out


def prove_system(sysm, graph, vo_files: dict[str, Path], work: Path) -> tuple[str, list[str]]:
    """Compile the per-system file in ``work`` against the nodes' compiled
    modules ``vo_files`` (node name -> ``.vo``), require its assumptions
    closed, re-check it with ``coqchk``; return the ``.v`` text and the
    theorem names."""
    from pyrosgen.proof.coqdriver import CoqDriver

    vtext = render_system_file(sysm, graph)
    coq_dir = work / "coq"
    coq_dir.mkdir(parents=True)
    for name, vo in vo_files.items():
        shutil.copyfile(vo, coq_dir / f"{name}.vo")
    vname = system_v_name(sysm.name)
    if vname[:-2] in vo_files:
        raise ToolFailure(f"a node is named {vname[:-2]}, the name of the system's Coq file; rename the system")
    (coq_dir / vname).write_text(vtext, encoding="ascii")
    drv = CoqDriver()
    drv.check_tools()
    drv.check_library()
    lib = (coq_dir, "RosgenNode")
    res = drv.coqc(coq_dir / vname, lib)
    thm = system_theorem(sysm.name)
    drv.check_assumptions(res.stdout, [f"{sysm.name}_target", thm])
    drv.coqchk(f"RosgenNode.{vname[:-2]}", lib)
    return vtext, ([thm, f"{sysm.name}_target"] + [f"{sysm.name}_link_{k}" for k in range(1, len(graph.links) + 1)]
                   + chain_theorems(sysm.name, graph))
