"""Helpers of the diagram tests: run Graphviz on DOT text and read back
what it understood (``dot -Tjson``)."""

from __future__ import annotations

import json
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

from pyrosgen.diagram import find_dot

REPO = Path(__file__).resolve().parent.parent.parent
LANDSHARK = REPO / "examples" / "landshark" / "landshark_controller.yaml"
MULTI = REPO / "examples" / "multi" / "multi_node.yaml"
KO_MODEL = REPO / "tests" / "frontend" / "models" / "ko_three_errors.yaml"


def _texts(ops) -> list[str]:
    return [op["text"] for op in ops or () if op.get("op") == "T"]


@dataclass
class Graph:
    """What ``dot`` parsed: clusters (name -> label text), nodes (name ->
    rendered text lines), edges (tail, head, attributes)."""

    clusters: dict[str, list[str]] = field(default_factory=dict)
    cluster_nodes: dict[str, set[str]] = field(default_factory=dict)
    nodes: dict[str, list[str]] = field(default_factory=dict)
    edges: list[dict] = field(default_factory=list)
    title: list[str] = field(default_factory=list)

    def edges_with_id(self, prefix: str) -> list[dict]:
        return [e for e in self.edges if e["id"].startswith(prefix)]


def parse_with_dot(dot_text: str) -> Graph:
    """Lay ``dot_text`` out with ``dot -Tjson`` (which must accept it) and
    return the graph as Graphviz understood it, texts as rendered."""
    proc = subprocess.run(
        [find_dot(), "-Tjson"], input=dot_text.encode(), capture_output=True, check=False
    )
    assert proc.returncode == 0, proc.stderr.decode()
    data = json.loads(proc.stdout)
    g = Graph(title=_texts(data.get("_ldraw_")))
    names = {}
    for obj in data["objects"]:
        names[obj["_gvid"]] = obj["name"]
    for obj in data["objects"]:
        if obj["name"].startswith("cluster"):
            g.clusters[obj["name"]] = _texts(obj.get("_ldraw_"))
            g.cluster_nodes[obj["name"]] = {names[i] for i in obj.get("nodes", [])}
        else:
            g.nodes[obj["name"]] = _texts(obj.get("_ldraw_"))
    for e in data.get("edges", []):
        g.edges.append(
            {
                "tail": names[e["tail"]],
                "head": names[e["head"]],
                "tailport": e.get("tailport"),
                "headport": e.get("headport"),
                "id": e.get("id", ""),
                "label": " ".join(_texts(e.get("_ldraw_"))),
            }
        )
    return g
