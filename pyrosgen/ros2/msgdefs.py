"""ROS 2's message definitions, read from the installed wheels.

For the target ``ros2`` (DESIGN.md rule 4.17) the standard message types
are ROS 2 Kilted's: every ``<prefix>/share/<pkg>/msg/<Type>.msg`` of the
installed packages, parsed with rosbags' ``.msg`` parser and turned into the
front end's raw definitions (:class:`pyrosgen.frontend.msgload._RawMsg`).
Unlike ROS 1 there are no ``time``/``duration`` built-in types:
``builtin_interfaces/Time`` is an ordinary message (``int32 sec``,
``uint32 nanosec``), and ``std_msgs/Header`` is ``stamp`` and
``frame_id`` (no ``seq``).
"""

from __future__ import annotations

from pathlib import Path

from pyrosgen.frontend.msgload import _PLACEHOLDER, _RawField, _RawMsg
from pyrosgen.frontend.msgmodel import PRIMITIVES
from pyrosgen.ros2.env import Ros2Install, Ros2Missing, find_ros2

__all__ = ["ros2_standard_defs", "Ros2MsgError"]

#: ROS 2's ``byte`` is an octet (rosidl C: ``uint8_t``); ``char`` is a
#: ``signed char`` in rosidl's C and an unsigned 8-bit value in its IDL:
#: left unsupported rather than guessed.
_ALIASES = {"byte": "uint8", "octet": "uint8"}

_CACHE: dict[Path, dict[str, _RawMsg]] = {}


class Ros2MsgError(Ros2Missing):
    """A message definition of the installation cannot be read (exit 2)."""


def _name(rosbags_name: str) -> str:
    """``pkg/msg/Type`` to ``pkg/Type``."""
    parts = rosbags_name.split("/")
    if len(parts) == 3 and parts[1] == "msg":
        return f"{parts[0]}/{parts[2]}"
    return rosbags_name


def _field(fname: str, desc) -> _RawField:
    from rosbags.interfaces import Nodetype

    nodetype, payload = desc
    card, size = "scalar", 0
    if nodetype in (Nodetype.ARRAY, Nodetype.SEQUENCE):
        card = "array" if nodetype == Nodetype.ARRAY else "sequence"
        (nodetype, payload), size = payload
    if nodetype == Nodetype.BASE:
        base, _bound = payload
        if base == "string":
            return _RawField(fname, "string", "string", card, size)
        if card == "sequence" and base in _ALIASES:
            # rosidl's C sequence of a byte is an octet sequence, not a uint8 one
            return _RawField(fname, "unsupported", base, card, size)
        base = _ALIASES.get(base, base)
        if base in PRIMITIVES:
            return _RawField(fname, "prim", base, card, size)
        return _RawField(fname, "unsupported", base, card, size)
    return _RawField(fname, "msg", _name(payload), card, size)


def ros2_standard_defs(install: Ros2Install | None = None) -> dict[str, _RawMsg]:
    """``pkg/Type`` -> definition, for every ``.msg`` file of the installed
    ROS 2 packages (read once per installation)."""
    inst = install or find_ros2()
    key = inst.prefix.resolve()
    if key in _CACHE:
        return _CACHE[key]
    from rosbags.typesys import get_types_from_msg

    out: dict[str, _RawMsg] = {}
    for f in sorted(inst.share_dir.glob("*/msg/*.msg")):
        pkg, typ = f.parent.parent.name, f.stem
        try:
            defs = get_types_from_msg(f.read_text(encoding="utf-8"), f"{pkg}/msg/{typ}")
        except Exception as exc:  # noqa: BLE001 - rosbags raises several kinds
            raise Ros2MsgError(f"{f}: cannot read this ROS 2 message definition: {' '.join(str(exc).split())}") from None
        _consts, fields = defs[f"{pkg}/msg/{typ}"]
        if len(fields) == 1 and fields[0][0] == _PLACEHOLDER:
            fields = []
        out[f"{pkg}/{typ}"] = _RawMsg(f"{pkg}/{typ}", tuple(_field(n, d) for n, d in fields))
    _CACHE[key] = out
    return out
