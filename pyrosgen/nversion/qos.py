"""The QoS record read a second time from the YAML file (N-version,
DESIGN.md rule 4.18 and section 7).

The QoS of a ROS 2 node's topics is not part of the model Coq proves
things about (it decides which messages arrive, an assumption on the
environment, section 6.1), so no printed model text carries it.  It reaches
the rcl wrapper from the front end's reading of the model file, written as
the record ``<node>.qos`` (:func:`pyrosgen.ros2.wrapper.qos_text`); this
module computes the same record from the YAML file without the front end,
from rule 4.18 alone, and ``build --ros2`` and ``verify --model`` require
both readings to agree.  It does not validate (the front end accepted the
file first) and raises :class:`ReadingError` on anything it does not
understand.
"""

from __future__ import annotations

from pathlib import Path

from pyrosgen.nversion.msgs import ReadingError
from pyrosgen.nversion.reader import Num, read_yaml

__all__ = ["QOS_HEADER", "qos_text", "check_qos_record"]

QOS_HEADER = "pyrosgen-qos 1"

# rule 4.18: rmw_qos_profile_default and rmw_qos_profile_sensor_data of
# rmw/qos_profiles.h (reliability, durability; their depths are replaced by queue_size)
_PROFILE = {"default": ("reliable", "volatile"), "sensor_data": ("best_effort", "volatile")}
_VALUES = {"reliability": ("reliable", "best_effort"), "durability": ("volatile", "transient_local")}


def _one(t: dict) -> tuple[str, str]:
    if "qos" not in t:
        return _PROFILE["default"]
    q = t["qos"]
    if isinstance(q, str):
        if q not in _PROFILE:
            raise ReadingError(f"topic {t.get('name')}: qos {q!r} is not a profile")
        return _PROFILE[q]
    if not isinstance(q, dict) or set(q) - {"profile", *_VALUES}:
        raise ReadingError(f"topic {t.get('name')}: qos {q!r} is not understood")
    prof = q.get("profile", "default")
    if not isinstance(prof, str) or prof not in _PROFILE:
        raise ReadingError(f"topic {t.get('name')}: qos profile {prof!r} is not a profile")
    rel, dur = _PROFILE[prof]
    rel, dur = q.get("reliability", rel), q.get("durability", dur)
    if rel not in _VALUES["reliability"] or dur not in _VALUES["durability"]:
        raise ReadingError(f"topic {t.get('name')}: qos ({rel!r}, {dur!r}) is not understood")
    return rel, dur


def qos_text(path, *, doc=None) -> str:
    """The QoS record of the model file at ``path``: a header line, then one
    line per topic in the model's order, ``topic NAME DIRECTION keep_last
    DEPTH RELIABILITY DURABILITY``."""
    if doc is None:
        doc = read_yaml(Path(path))
    if not isinstance(doc, dict) or not isinstance(doc.get("topics"), list):
        raise ReadingError(f"{path}: no list of topics")
    lines = [QOS_HEADER]
    for t in doc["topics"]:
        if not isinstance(t, dict) or not isinstance(t.get("queue_size"), Num) \
                or not isinstance(t["queue_size"].value, int):
            raise ReadingError(f"{path}: a topic without an integer queue_size")
        rel, dur = _one(t)
        lines.append(f"topic {t['name']} {t['direction']} keep_last {int(t['queue_size'].text)} {rel} {dur}")
    return "".join(line + "\n" for line in lines)


def check_qos_record(path, record: str, *, what: str) -> None:
    """Raise :class:`pyrosgen.nversion.check.NVersionMismatch` (exit 2)
    unless ``record`` (the QoS record ``what`` names: the front end's
    reading, or a build folder's ``<node>.qos``) is, byte for byte, the QoS
    record of the model file at ``path`` read by this module."""
    from pyrosgen.nversion.check import NVersionMismatch, differing_lines

    name = Path(path).name
    try:
        expected = qos_text(path)
    except Exception as exc:  # noqa: BLE001 - whatever stops the second reading is a disagreement (exit 2)
        detail = f"{type(exc).__name__}: {exc}" if not isinstance(exc, ReadingError) else str(exc)
        raise NVersionMismatch(f"the two readings of the model disagree: the second, independent reading of "
                               f"{name} cannot read its QoS", [f"  {detail}"]) from None
    lines = differing_lines(expected, record, what=what)
    if lines:
        raise NVersionMismatch(f"the two readings of the model disagree: {what} is not the QoS of {name} "
                               "read independently of the front end (rule 4.18)", lines)
