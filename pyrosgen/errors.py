"""Errors and diagnostics of pyrosgen.

Every problem found in user input is a :class:`Diagnostic` that renders like a
compiler message, ``FILE:LINE:COL: error: MESSAGE``.  Problems are collected
(never only the first one) and raised together as :class:`InvalidNodeModel`.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "Diagnostic",
    "PyrosgenError",
    "InvalidNodeModel",
    "show",
    "escape",
]


@dataclass(frozen=True)
class Diagnostic:
    """One problem in a user file.

    ``line`` and ``col`` are 1-based; both are ``None`` when the problem is about
    the file as a whole (missing, unreadable, too large).
    """

    file: str
    line: int | None
    col: int | None
    message: str
    severity: str = "error"

    def __str__(self) -> str:
        # Messages quote user text with show(); escape() is a safety net so
        # that a rendered diagnostic is always one printable ASCII line.
        message = escape(self.message, keep_quotes=True)
        if self.line is None:
            return f"{self.file}: {self.severity}: {message}"
        col = self.col if self.col is not None else 1
        return f"{self.file}:{self.line}:{col}: {self.severity}: {message}"


class PyrosgenError(Exception):
    """Base class of every error pyrosgen reports to its user."""


class InvalidNodeModel(PyrosgenError):
    """The node model (or a message definition it uses) is invalid.

    ``diagnostics`` lists every problem found, in file then position order.
    """

    def __init__(self, diagnostics: list[Diagnostic] | tuple[Diagnostic, ...]):
        self.diagnostics: tuple[Diagnostic, ...] = tuple(diagnostics)
        super().__init__(str(self))

    def __str__(self) -> str:
        return "\n".join(str(d) for d in self.diagnostics)


def escape(text: str, keep_quotes: bool = False) -> str:
    """``text`` with every character outside printable ASCII escaped
    (``\\n`` becomes ``\\x0a``, ``é`` becomes ``\\xe9``), and quotes and
    backslashes escaped unless ``keep_quotes``."""
    out = []
    for ch in text:
        if not keep_quotes and ch in "'\\":
            out.append("\\" + ch)
        elif " " <= ch <= "~":
            out.append(ch)
        else:
            code = ord(ch)
            if code <= 0xFF:
                out.append(f"\\x{code:02x}")
            elif code <= 0xFFFF:
                out.append(f"\\u{code:04x}")
            else:
                out.append(f"\\U{code:08x}")
    return "".join(out)


def show(value: object, limit: int = 100) -> str:
    """Quote a user-supplied value for a one-line message.

    Non-printable and non-ASCII characters are escaped (so a newline or a
    comment terminator in a name cannot break the message or anything that
    embeds it) and long values are shortened.
    """
    s = escape(value if isinstance(value, str) else str(value))
    if len(s) > limit:
        s = s[: limit - 3] + "..."
    return f"'{s}'"
