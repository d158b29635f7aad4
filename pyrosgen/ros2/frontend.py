"""The front end for the target ``ros2`` (DESIGN.md rule 4.17).

The same model file is read with ROS 2's message definitions
(:mod:`pyrosgen.ros2.msgdefs`) instead of ROS 1 Noetic's; every rule of
section 4 applies unchanged.  A problem that the ROS 2 reading finds and the
ROS 1 reading does not (``header.seq``, ``stamp.nsec``, a type ROS 2 does not
have, ``stamp: now`` on a ``builtin_interfaces/Time`` stamp) is reported
under rule 4.17, with the rule it breaks for ROS 2.  Then the features this
version does not yet build for ROS 2 are refused, each at its place:

- custom messages (``msg_paths``): they would need rosidl's generators;
- stamps (rule 4.13): the proved glue stores ``ros_time_sec()`` (an
  ``unsigned int``) into ``stamp.sec``, which is ROS 2's ``int32``, and the
  nanoseconds into ``nsec``, which ROS 2 calls ``nanosec``: the library
  proves no such store yet (refused by the ROS 2 reading itself, since no
  ROS 2 header has a stamp of ROS 1's type ``time``).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

from pyrosgen.errors import Diagnostic, InvalidNodeModel
from pyrosgen.frontend.model import NodeModel
from pyrosgen.frontend.validate import load_model
from pyrosgen.frontend.yamlsrc import YMap, load_yaml
from pyrosgen.ros2.env import Ros2Install
from pyrosgen.ros2.msgdefs import ros2_standard_defs

__all__ = ["TARGET_RULE", "load_model_ros2"]

#: The rule of DESIGN.md section 4 on the two targets.
TARGET_RULE = "4.17"


def _relabel(exc: InvalidNodeModel, path: Path) -> InvalidNodeModel:
    """The ROS 2 reading's problems, those the ROS 1 reading does not have
    (at the same place) under rule 4.17."""
    try:
        load_model(path)
        ros1: set[tuple[int | None, int | None]] = set()
    except InvalidNodeModel as e1:
        ros1 = {(d.line, d.col) for d in e1.diagnostics}
    out = []
    for d in exc.diagnostics:
        if d.line is not None and (d.line, d.col) not in ros1:
            was = f", rule {d.rule}" if d.rule else ""
            if d.rule == "4.13":
                was += (": ROS 2's header.stamp is a builtin_interfaces/Time (int32 sec, uint32 nanosec), "
                        "which the proved library does not stamp yet")
            d = Diagnostic(d.file, d.line, d.col,
                           f"{d.message} (target ros2: ROS 2 Kilted's message definitions{was}; "
                           "the ROS 1 target accepts it)", d.severity, TARGET_RULE)
        out.append(d)
    return InvalidNodeModel(out)


def _msg_paths_refusal(path: Path) -> list[Diagnostic]:
    """A non-empty ``msg_paths``: custom messages are not built for ROS 2
    in this version (rule 4.17)."""
    try:
        root = load_yaml(path).root
    except InvalidNodeModel:
        return []  # reported by the model's reading
    mp = root.get("msg_paths") if isinstance(root, YMap) else None
    if mp is None or not getattr(mp, "items", None):
        return []
    return [Diagnostic(str(path), mp.line, mp.col,
                       "msg_paths: custom message types are not built for the target ros2 yet "
                       "(they need rosidl's C generators); use ROS 2's standard types", rule=TARGET_RULE)]


def load_model_ros2(path: str | Path, install: Ros2Install | None = None) -> NodeModel:
    """Read and validate the model file at ``path`` for the target ros2.

    Raises :class:`InvalidNodeModel` (exit 1) with every problem found, and
    :class:`pyrosgen.ros2.env.Ros2Missing` (exit 2) without a ROS 2
    installation."""
    path = Path(path)
    defs = ros2_standard_defs(install)
    pre = _msg_paths_refusal(path)
    try:
        model = load_model(path, standard_msgs=defs)
    except InvalidNodeModel as exc:
        relabelled = _relabel(exc, path).diagnostics
        raise InvalidNodeModel(sorted([*pre, *relabelled], key=lambda d: (d.file != str(path), d.line or 0,
                                                                          d.col or 0))) from None
    if pre:
        raise InvalidNodeModel(pre)
    # rule 4.18: the QoS is the ROS 2 target's; the ROS 1 reading's warning that it is ignored does not apply
    return dataclasses.replace(model, warnings=())


