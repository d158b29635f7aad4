"""The C++ headers of the standard ROS 1 message types, and the Debian
packages that ship them.

The front end knows every message type of ROS 1 Noetic's standard message
packages (rosbags' Noetic store, :mod:`pyrosgen.frontend.msgload`); a node
that uses one is *built* against its roscpp header ``<pkg>/<Type>.h``.
:data:`DEBIAN_DEV` names, for each of these packages, the Debian package
that ships its headers (``scripts/deps.sh``, run by ``make deps``,
installs them all); :func:`missing_headers` lists the types of a model
whose header is not installed, so that ``pyrosgen build`` refuses the
model before proving it, naming the package to install, and ``pyrosgen
check`` says so in a note (the model is valid whatever the machine; only
building it needs the headers).  Types of the model's ``msg_paths`` are
not looked for: build generates their headers.
"""

from __future__ import annotations

import glob
import os
from dataclasses import dataclass
from pathlib import Path

from pyrosgen.frontend.model import NodeModel, Pos

__all__ = ["DEBIAN_DEV", "MissingHeader", "include_roots", "missing_headers"]

#: ROS 1 message package -> the Debian package with its C++ headers.
DEBIAN_DEV: dict[str, str] = {
    "std_msgs": "libstd-msgs-dev",
    "geometry_msgs": "libgeometry-msgs-dev",
    "sensor_msgs": "libsensor-msgs-dev",
    "nav_msgs": "libnav-msgs-dev",
    "actionlib_msgs": "libactionlib-msgs-dev",
    "diagnostic_msgs": "libdiagnostic-msgs-dev",
    "shape_msgs": "libshape-msgs-dev",
    "stereo_msgs": "libstereo-msgs-dev",
    "trajectory_msgs": "libtrajectory-msgs-dev",
    "visualization_msgs": "libvisualization-msgs-dev",
    "rosgraph_msgs": "libros-rosgraph-msgs-dev",
    "actionlib": "libactionlib-dev",
    "dynamic_reconfigure": "libdynamic-reconfigure-config-init-mutex-dev",
    "bond": "libbond-dev",
    "roscpp": "libroscpp-msg-dev",
}

#: Where ROS's headers are looked for besides ``CPATH`` and ``CPLUS_INCLUDE_PATH``.
_ROOTS = ("/usr/include", "/usr/local/include", "/opt/ros/*/include")


def include_roots() -> list[Path]:
    """The folders a message header is looked for in: those of
    ``CPLUS_INCLUDE_PATH`` and ``CPATH``, ``/usr/include``,
    ``/usr/local/include``, ``/opt/ros/<distro>/include``."""
    roots = [p for var in ("CPLUS_INCLUDE_PATH", "CPATH") for p in os.environ.get(var, "").split(":") if p]
    for pattern in _ROOTS:
        roots += sorted(glob.glob(pattern))
    return [Path(r) for r in roots]


@dataclass(frozen=True)
class MissingHeader:
    """A message type of the model whose C++ header is not installed."""

    msg_type: str          #: ``trajectory_msgs/JointTrajectory``
    header: str            #: ``trajectory_msgs/JointTrajectory.h``
    debian: str | None     #: the Debian package that ships it, if any
    topic: str | None      #: the first topic of that type, if any
    pos: Pos               #: that topic's position in the model file

    def message(self) -> str:
        where = f" (topic {self.topic})" if self.topic else ""
        fix = (f"install the Debian package {self.debian} (make deps installs it)" if self.debian
               else "install the ROS package that ships it")
        return f"{self.msg_type}{where}: its C++ header {self.header} is not installed: {fix}"


def missing_headers(model: NodeModel) -> list[MissingHeader]:
    """The standard message types ``model`` uses (its topics' types and
    the types nested in them) whose C++ header is in none of
    :func:`include_roots`."""
    roots = include_roots()
    out = []
    for m in model.messages:
        if m.is_pseudo or m.package is None:
            continue
        if any((Path(folder) / m.package / "msg" / f"{m.short_name}.msg").is_file() for folder in model.msg_paths):
            continue
        header = f"{m.package}/{m.short_name}.h"
        if any((root / header).is_file() for root in roots):
            continue
        topic = next((t for t in model.topics if t.msg_type == m.name), None)
        out.append(MissingHeader(m.name, header, DEBIAN_DEV.get(m.package), topic.name if topic else None,
                                 topic.pos if topic else Pos(0, 0)))
    return out
