"""One check of ``pyrosgen verify``: its name, verdict, summary and the
lines that say what failed.  A module of its own so that the checks that
live in their own modules (:mod:`pyrosgen.verify.package_check`) and the
driver (:mod:`pyrosgen.verify.recheck`) share it without importing each
other."""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["Check"]


@dataclass
class Check:
    name: str
    ok: bool
    summary: str
    details: list[str] = field(default_factory=list)
