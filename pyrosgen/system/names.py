"""ROS 1 graph names in a system: namespaces, resolution, remappings.

The rules (DESIGN.md section 10, "Systems"), as roscpp applies them to a
node started with ``ns`` and ``<remap from= to=>`` by roslaunch:

- a *namespace* is ``/`` or a global name ``/a/b`` (a relative one, ``a/b``,
  is read under ``/``: roslaunch's ``ns`` of a top-level node);
- a *global* topic name ``/x/y`` resolves to itself; a *relative* one
  ``x/y`` to ``NS/x/y`` (``/x/y`` under ``/``); a *private* one ``~x``
  would resolve to ``NS/NODE/x``: node models refuse them (rule 4.x of
  :mod:`pyrosgen.frontend.names`) and so do remappings here;
- a remapping ``from: to`` has both sides resolved in the node's namespace;
  a topic whose resolved name is the resolved ``from`` is renamed to the
  resolved ``to``.  roscpp applies the remappings once, not transitively:
  a remapping whose target is the source of another one of the same node
  (a chain ``a -> b``, ``b -> c``, or a cycle ``a -> b``, ``b -> a``) is
  refused as ambiguous (rule 10.4).
"""

from __future__ import annotations

import re

from pyrosgen.frontend.names import topic_name_problem

__all__ = ["namespace_problem", "node_name_problem", "resolve", "join"]

_BASE_RE = re.compile(r"[A-Za-z][A-Za-z0-9_]*")


def namespace_problem(ns: str) -> str | None:
    """Why ``ns`` is not a ROS namespace, or ``None``."""
    if ns == "/":
        return None
    if ns.startswith("~"):
        return "a namespace cannot be private (~)"
    return topic_name_problem(ns)


def node_name_problem(name: str) -> str | None:
    """Why ``name`` is not a ROS node base name, or ``None``."""
    if not _BASE_RE.fullmatch(name):
        return "a node name is a letter followed by letters, digits and '_' (no '/')"
    return None


def _norm_ns(ns: str) -> str:
    if ns in ("", "/"):
        return "/"
    return ns if ns.startswith("/") else "/" + ns


def join(ns: str, name: str) -> str:
    """``name`` (relative) under namespace ``ns``."""
    ns = _norm_ns(ns)
    return ns + name if ns.endswith("/") else ns + "/" + name


def resolve(ns: str, name: str) -> str:
    """The resolved (global) name of topic ``name`` in namespace ``ns``."""
    if name.startswith("/"):
        return name
    return join(ns, name)
