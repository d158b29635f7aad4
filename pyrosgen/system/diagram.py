"""``pyrosgen system diagram``: the nodes of a system and the topics
between them, drawn from the model before anything runs (like
rqt_graph), and on request one chain with its relations through every
node (``--chain N``, the numbering of the system's certificate)."""

from __future__ import annotations

import os
from pathlib import Path

from pyrosgen.diagram import dot_html, run_dot, write_atomic
from pyrosgen.errors import UserError
from pyrosgen.render import render, source_label

__all__ = ["system_context", "render_system_dot", "write_system_diagram"]


def system_context(sysm, graph, chain: int | None = None) -> dict:
    """The template's context; ``chain`` (from 1) highlights one chain and
    labels its edges with the relations it passes through."""
    if chain is not None and not 1 <= chain <= len(graph.chains):
        raise UserError(f"--chain {chain}: the system has {len(graph.chains)} chain(s) from an external input "
                        "to an external output (numbered from 1, as in its certificate)")
    ch = graph.chains[chain - 1] if chain is not None else None
    on_nodes = {h.node.full_name for h in ch.hops} if ch else set()
    on_topics = ({ch.hops[0].src} | {h.dst for h in ch.hops}) if ch else set()
    nid = {sn.full_name: f"n{i}" for i, sn in enumerate(sysm.nodes)}
    names = sorted(set(graph.publishers) | set(graph.subscribers))
    tid = {g: f"t{i}" for i, g in enumerate(names)}
    nodes = [{"id": nid[sn.full_name], "name": sn.full_name, "node": sn.model.name,
              "period_ms": sn.model.period_ms, "on_chain": sn.full_name in on_nodes} for sn in sysm.nodes]
    topics = [{"id": tid[g], "name": g, "type": graph.topic_type(g) or "",
               "external": "input" if g in sysm.inputs else "output" if g in sysm.outputs else None,
               "on_chain": g in on_topics} for g in names]
    hop_in = {(h.node.full_name, h.src): h for h in ch.hops} if ch else {}
    hop_out = {(h.node.full_name, h.dst): h for h in ch.hops} if ch else {}
    edges = []
    for g in names:
        for sn, _ in graph.publishers.get(g, []):
            h = hop_out.get((sn.full_name, g))
            label = "<br/>".join(f"{o.output_source} -&gt; {o.field_text}" for o in h.outputs) if h else ""
            edges.append({"tail": nid[sn.full_name], "head": tid[g], "label": label, "on_chain": h is not None})
        for sn, _ in graph.subscribers.get(g, []):
            h = hop_in.get((sn.full_name, g))
            label = "<br/>".join(f"{r.field_text} -&gt; {r.input_target}" for r in h.inputs) if h else ""
            edges.append({"tail": tid[g], "head": nid[sn.full_name], "label": label, "on_chain": h is not None})
    path = None
    if ch:
        path = " -> ".join([ch.hops[0].src] + [f"{h.node.full_name} -> {h.dst}" for h in ch.hops])
    return {"source": source_label(sysm.source.name), "system": sysm.name, "nodes": nodes, "topics": topics,
            "edges": edges, "chain": {"index": chain, "path": path} if ch else None}


def _finalize(value):
    # labels built here hold their own <br/> and escaped arrows; every other
    # value is escaped
    return value if isinstance(value, _Raw) else dot_html(value)


class _Raw(str):
    pass


def render_system_dot(sysm, graph, chain: int | None = None) -> str:
    ctx = system_context(sysm, graph, chain)
    for e in ctx["edges"]:
        # the relations' texts are checked names and paths; escape them, keep the line breaks
        e["label"] = _Raw("<br/>".join(dot_html(part).replace("-&amp;gt;", "-&gt;")
                                       for part in e["label"].split("<br/>"))) if e["label"] else ""
    return render("system.dot.j2", finalize=_finalize, **ctx)


def write_system_diagram(sysm, graph, output: str | os.PathLike[str], fmt: str, chain: int | None = None) -> bool:
    text = os.fspath(output)
    if not text or text.endswith(("/", os.sep)) or os.path.basename(text) in (".", ".."):
        raise UserError(f"{text!r} names a folder, not a file; give a file name")
    dot_text = render_system_dot(sysm, graph, chain)
    data = dot_text.encode("utf-8") if fmt == "dot" else run_dot(dot_text, fmt)
    return write_atomic(Path(text), data)
