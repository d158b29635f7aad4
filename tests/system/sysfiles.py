"""Writing small node models and system files for the system tests."""

from __future__ import annotations

from pathlib import Path

import yaml


def node_model(folder: Path, name: str, *, subs=(), pubs=(), period_ms: int = 20, comment: str = "",
               qos: dict | None = None) -> Path:
    """A node model ``folder/<name>.yaml`` with an Embedded Coder style
    controller: ``subs`` are ``(topic, type, [fields], timeout_ms or None)``,
    each field feeding an input ``I<k>``; ``pubs`` are ``(topic, type,
    [fields])``, each field written from an output ``O<k>``; ``qos``: topic
    -> its ``qos`` value (rule 4.18)."""
    inputs, outputs, topics, rin, rout = {}, {}, [], [], []
    for topic, typ, fields, timeout in subs:
        t = {"name": topic, "direction": "subscribe", "type": typ, "queue_size": 1}
        if timeout is not None:
            t["timeout_ms"] = timeout
        topics.append(t)
        for f in fields:
            k = f"I{len(inputs) + 1}"
            inputs[k] = "float64"
            rin.append({"topic": topic, "field": f, "input": k})
    for topic, typ, fields in pubs:
        topics.append({"name": topic, "direction": "publish", "type": typ, "queue_size": 1})
        for f in fields:
            k = f"O{len(outputs) + 1}"
            outputs[k] = "float64"
            rout.append({"output": k, "topic": topic, "field": f})
    model = {
        "node": {"name": name, "period_ms": period_ms},
        "controller": {"name": "Ctl", "inputs": {"name": "Ctl_U", "fields": inputs or {"Unused": "float64"}},
                       "outputs": {"name": "Ctl_Y", "fields": outputs or {"Unused": "float64"}}},
        "topics": topics,
        "relations": {"inputs": rin, "outputs": rout},
    }
    for t in topics:
        if qos and t["name"] in qos:
            t["qos"] = qos[t["name"]]
    p = folder / f"{name}.yaml"
    p.write_text((f"# {comment}\n" if comment else "") + yaml.safe_dump(model, sort_keys=False))
    return p


def system_file(folder: Path, nodes, inputs=(), outputs=(), shared=None, name: str = "sys") -> Path:
    """A system file ``folder/system.yaml`` (``nodes``: the entries as dicts)."""
    doc = {"system": {"name": name}, "nodes": list(nodes),
           "external": {"inputs": list(inputs), "outputs": list(outputs)}}
    if shared is not None:
        doc["shared"] = list(shared)
    p = folder / "system.yaml"
    p.write_text(yaml.safe_dump(doc, sort_keys=False))
    return p


TWIST = "geometry_msgs/Twist"
VEC3 = "geometry_msgs/Vector3"


def chain(folder: Path, **kw) -> Path:
    """A two-node chain: ``a`` relays /src (Twist linear.x, angular.z) to
    /mid, ``b`` reads /mid and publishes /out (Vector3 x, y)."""
    node_model(folder, "a", subs=[("/src", TWIST, ["linear.x"], None)],
               pubs=[("/mid", TWIST, ["linear.x", "angular.z"])])
    node_model(folder, "b", subs=[("/mid", TWIST, ["linear.x", "angular.z"], None)],
               pubs=[("/out", VEC3, ["x", "y"])])
    return system_file(folder, [{"model": "a.yaml"}, {"model": "b.yaml"}], inputs=["/src"], outputs=["/out"], **kw)
