"""The front end for the target ``ros2`` (DESIGN.md rule 4.17).

The same model file is read with ROS 2's message definitions
(:mod:`pyrosgen.ros2.msgdefs`) instead of ROS 1 Noetic's; every rule of
section 4 applies unchanged.  A problem that the ROS 2 reading finds and the
ROS 1 reading does not (``header.seq``, ``stamp.nsec``, a type ROS 2 does not
have) is reported under rule 4.17, with the rule it breaks for ROS 2.

Stamps (rule 4.13) are ROS 2's: ``header.stamp`` is a
``builtin_interfaces/Time`` (``int32 sec``, ``uint32 nanosec``), and the
proved glue stores ``(int)ros_time_sec()`` into ``sec`` (the seconds
modulo 2^32 read as a signed number: negative past 2038, as gcc converts)
and ``ros_time_nsec()`` into ``nanosec``, or copies both from a
subscribed topic's stamp (``DDC.stamp_sec``,
:func:`pyrosgen.frontend.rule_stamps.time_type`).

Custom messages (``msg_paths``) are read as for ROS 1 and built with
rosidl's generators (:mod:`pyrosgen.ros2.rosidl`); what a ``.msg`` file may
say for ROS 1 but not for ROS 2 is refused first, at its place, under rule
4.17 (:func:`ros2_msg_problems`): ROS 1's built-in ``time`` and
``duration`` (ROS 2's ``builtin_interfaces/Time`` is ``int32 sec``,
``uint32 nanosec``), ``byte`` (an ``int8`` in ROS 1, an octet in ROS 2)
and ``char`` (deprecated in ROS 2), a bare ``Header`` (ROS 2 reads it as a type of the message's own
package: write ``std_msgs/Header``), and the names rosidl refuses (field
names in lower case without ``__`` or a trailing ``_``, constant names in
upper case, message names starting with an upper-case letter).
"""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

from pyrosgen.errors import Diagnostic, InvalidNodeModel
from pyrosgen.frontend.model import NodeModel
from pyrosgen.frontend.msgload import _display
from pyrosgen.frontend.validate import load_model
from pyrosgen.frontend.yamlsrc import YMap, load_yaml, read_text
from pyrosgen.ros2.env import Ros2Install
from pyrosgen.ros2.msgdefs import ros2_standard_defs

__all__ = ["TARGET_RULE", "load_model_ros2", "ros2_msg_problems"]

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
            d = Diagnostic(d.file, d.line, d.col,
                           f"{d.message} (target ros2: ROS 2 Kilted's message definitions{was}; "
                           "the ROS 1 target accepts it)", d.severity, TARGET_RULE)
        out.append(d)
    return InvalidNodeModel(out)


#: rosidl_adapter's patterns (``rosidl_adapter/parser.py``): what ROS 2
#: accepts as a package, field, constant and message name.
_ROS2_FIELD = re.compile(r"(?!.*__)(?!.*_$)[a-z][a-z0-9_]*")
_ROS2_CONSTANT = re.compile(r"[A-Z]([A-Z0-9_]?[A-Z0-9]+)*")
_ROS2_MESSAGE = re.compile(r"[A-Z][A-Za-z0-9]*")
_LINE = re.compile(r"(\s*)([A-Za-z0-9_/]+)((?:\[[^\]]*\])?)(\s+)([A-Za-z0-9_]+)")
#: ROS 1 base types with no ROS 2 counterpart of the same meaning
_ROS1_ONLY = {
    "time": "ROS 1's built-in type time does not exist in ROS 2: use builtin_interfaces/Time "
            "(int32 sec, uint32 nanosec)",
    "duration": "ROS 1's built-in type duration does not exist in ROS 2: use builtin_interfaces/Duration "
                "(int32 sec, uint32 nanosec)",
    "byte": "byte is an int8 in ROS 1 and an unsigned octet in ROS 2: write int8 or uint8",
    "char": "char is deprecated in ROS 2 (rosidl reads it as uint8 in a .msg file, as a character in IDL): "
            "write uint8",
    "Header": "a bare Header is std_msgs/Header in ROS 1 but a type of the message's own package in ROS 2: "
              "write std_msgs/Header",
}


def _msg_folders(path: Path) -> list[Path]:
    """The folders the model's ``msg_paths`` names that exist (the others
    are reported by the model's reading, rule 4.5)."""
    try:
        root = load_yaml(path).root
    except InvalidNodeModel:
        return []  # reported by the model's reading
    mp = root.get("msg_paths") if isinstance(root, YMap) else None
    out = []
    for item in getattr(mp, "items", None) or []:
        text = getattr(item, "value", None)
        if isinstance(text, str) and text and "\x00" not in text:
            folder = Path(text) if Path(text).is_absolute() else path.parent / text
            if folder.is_dir():
                out.append(folder)
    return out


def _msg_file_problems(f: Path, installed: frozenset[str]) -> list[Diagnostic]:
    shown = _display(f)
    out: list[Diagnostic] = []
    if f.parent.parent.name in installed:
        out.append(Diagnostic(shown, None, None, f"package {f.parent.parent.name!r} is a package of the ROS 2 "
                              "installation: rosidl builds one library per package, and the node would load the "
                              "installed one; name the custom package otherwise (target ros2)", rule=TARGET_RULE))
    if not _ROS2_MESSAGE.fullmatch(f.stem):
        out.append(Diagnostic(shown, None, None, f"message name {f.stem!r} is not a ROS 2 message name "
                              "(an upper-case letter, then letters and digits)", rule=TARGET_RULE))
    if not _ROS2_FIELD.fullmatch(f.parent.parent.name):
        out.append(Diagnostic(shown, None, None, f"package name {f.parent.parent.name!r} is not a ROS 2 package "
                              "name (lower case, digits and '_', no '__', not ending with '_')", rule=TARGET_RULE))
    try:
        text = read_text(f, what="message definition", rule="4.5", regular_only=True)
    except InvalidNodeModel:
        return out  # reported by the model's reading (rule 4.5)
    for i, line in enumerate(text.split("\n"), start=1):
        code = line.split("#", 1)[0].rstrip()
        m = _LINE.match(code)
        if m is None:
            continue
        typ, name = m.group(2), m.group(5)
        const = "=" in code[m.end(5):].lstrip()[:1]
        tcol, ncol = len(m.group(1)) + 1, m.start(5) + 1
        if typ in _ROS1_ONLY:
            out.append(Diagnostic(shown, i, tcol, f"field {name!r}: {_ROS1_ONLY[typ]} (target ros2; the ROS 1 "
                                  "target accepts it)", rule=TARGET_RULE))
        elif const and not _ROS2_CONSTANT.fullmatch(name):
            out.append(Diagnostic(shown, i, ncol, f"constant name {name!r} is not a ROS 2 constant name (upper "
                                  "case, digits and '_'; target ros2)", rule=TARGET_RULE))
        elif not const and not _ROS2_FIELD.fullmatch(name):
            out.append(Diagnostic(shown, i, ncol, f"field name {name!r} is not a ROS 2 field name (lower case, "
                                  "digits and '_', no '__', not ending with '_'; target ros2)", rule=TARGET_RULE))
    return out


def ros2_msg_problems(path: Path, installed: frozenset[str] = frozenset()) -> list[Diagnostic]:
    """What the custom ``.msg`` files of the model's ``msg_paths`` say that
    ROS 1 accepts and ROS 2 (rosidl) does not, at its place (rule 4.17);
    ``installed``: the message packages of the ROS 2 installation, which a
    custom package must not be."""
    out: list[Diagnostic] = []
    for folder in _msg_folders(path):
        for f in sorted(folder.glob("*/msg/*.msg")):
            if f.is_file():
                out.extend(_msg_file_problems(f, installed))
    return out


def load_model_ros2(path: str | Path, install: Ros2Install | None = None) -> NodeModel:
    """Read and validate the model file at ``path`` for the target ros2.

    Raises :class:`InvalidNodeModel` (exit 1) with every problem found, and
    :class:`pyrosgen.ros2.env.Ros2Missing` (exit 2) without a ROS 2
    installation."""
    path = Path(path)
    defs = ros2_standard_defs(install)
    pre = ros2_msg_problems(path, frozenset(name.split("/", 1)[0] for name in defs))
    try:
        model = load_model(path, standard_msgs=defs)
    except InvalidNodeModel as exc:
        # a line of a .msg file that ROS 2 refuses is reported once, as ROS 2 refuses it
        seen = {(d.file, d.line) for d in pre}
        relabelled = [d for d in _relabel(exc, path).diagnostics if (d.file, d.line) not in seen]
        raise InvalidNodeModel(sorted([*pre, *relabelled], key=lambda d: (d.file != str(path), d.file, d.line or 0,
                                                                          d.col or 0))) from None
    if pre:
        raise InvalidNodeModel(pre)
    # rule 4.18: the QoS is the ROS 2 target's; the ROS 1 reading's warning that it is ignored does not apply
    return dataclasses.replace(model, warnings=())


