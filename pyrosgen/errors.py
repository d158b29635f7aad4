"""Errors and diagnostics of pyrosgen.

Every problem found in user input is a :class:`Diagnostic` that renders like a
compiler message, ``FILE:LINE:COL: error: MESSAGE``.  Problems are collected
(never only the first one) and raised together as :class:`InvalidNodeModel`.

Every exception pyrosgen raises for its user belongs to one family with two
bases: :class:`UserError` (exit code 1) and :class:`ToolFailure` (exit
code 2); :func:`pyrosgen.cli.main` is the one place that turns them into
messages and exit codes.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

__all__ = [
    "Diagnostic",
    "Context",
    "PyrosgenError",
    "UserError",
    "ToolFailure",
    "DetailedFailure",
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
    #: The rule of DESIGN.md section 4 that the problem breaks (``"4.6"``),
    #: shown at the end of the message as ``[rule 4.6]``.
    rule: str | None = None

    def __str__(self) -> str:
        # Messages quote user text with show(); escape() is a safety net so
        # that a rendered diagnostic is always one printable ASCII line.
        message = escape(self.message, keep_quotes=True)
        if self.rule:
            message += f" [rule {self.rule}]"
        if self.line is None:
            return f"{self.file}: {self.severity}: {message}"
        col = self.col if self.col is not None else 1
        return f"{self.file}:{self.line}:{col}: {self.severity}: {message}"


@dataclass(frozen=True)
class Context:
    """What a report may name: the command, the model file and the output
    folder (for "nothing written to OUT")."""

    command: str = ""
    model: str = ""
    output: str = ""

    @property
    def nothing(self) -> str:
        return f"nothing written to {self.output}" if self.output else ""


class PyrosgenError(Exception):
    """Base class of every error pyrosgen reports to its user.

    Every error derives from exactly one of the two bases below, which fix
    its exit code (DESIGN.md section 8): :class:`UserError` (1) for what the
    user can fix (the model, the controller folder, the output folder),
    :class:`ToolFailure` (2) for a proof or a tool that failed.  The command
    line's one handler prints :meth:`report` and exits with
    :attr:`exit_code`."""

    exit_code = 2

    def report(self, ctx: Context) -> list[str]:
        """The lines printed on stderr (by default one line, with the
        "nothing written" note when there is an output folder)."""
        text = " ".join(str(self).split())
        return [f"pyrosgen: error: {text}" + (f"; {ctx.nothing}" if ctx.nothing else "")]


class UserError(PyrosgenError):
    """The user's input is wrong (exit code 1)."""

    exit_code = 1


class ToolFailure(PyrosgenError):
    """A proof, a tool or pyrosgen itself failed (exit code 2)."""

    exit_code = 2


class DetailedFailure(ToolFailure):
    """A tool failure with a one-line ``summary`` and the tool's own
    ``lines`` (compiler-style diagnostics or output) shown after it."""

    def __init__(self, summary: str, lines: Sequence[str] = ()):
        self.summary = summary
        self.lines = tuple(lines)
        super().__init__(summary if not self.lines else summary + "\n" + "\n".join(self.lines))

    def report(self, ctx: Context) -> list[str]:
        head = f"pyrosgen: error: {self.summary}" + (f"; {ctx.nothing}" if ctx.nothing else "")
        return [head, *self.lines]


class InvalidNodeModel(UserError):
    """The node model (or a message definition it uses) is invalid.

    ``diagnostics`` lists every problem found, in file then position order.
    """

    def __init__(self, diagnostics: list[Diagnostic] | tuple[Diagnostic, ...]):
        self.diagnostics: tuple[Diagnostic, ...] = tuple(diagnostics)
        super().__init__(str(self))

    def __str__(self) -> str:
        return "\n".join(str(d) for d in self.diagnostics)

    def report(self, ctx: Context) -> list[str]:
        return [str(self)]


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
