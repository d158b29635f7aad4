"""What pyrosgen writes on the terminal: verbosity and colour.

- ``--verbose`` (``-v``) makes every external command (coqc, coqchk,
  ocamlopt, gcc, g++, gencpp, ...) print itself before it runs and its exit
  code and time after it, on stderr.
- Colour (``error:`` in red, ``warning:`` in yellow, ``note:`` in cyan) only
  when stderr is a terminal, ``NO_COLOR`` is unset and ``TERM`` is not
  ``dumb`` (https://no-color.org); ``PYROSGEN_COLOR=always``/``never``
  overrides.
"""

from __future__ import annotations

import os
import re
import shlex
import sys
from collections.abc import Sequence

#: Set by the command line's ``--verbose``.
VERBOSE = False

_COLOURS = {"error": "\033[1;31m", "warning": "\033[1;33m", "note": "\033[1;36m"}
_RESET = "\033[0m"
_SEVERITY = re.compile(r"\b(error|warning|note):")


def use_colour(stream=None) -> bool:
    """Whether to colour what goes to ``stream`` (default: stderr)."""
    forced = os.environ.get("PYROSGEN_COLOR", "").lower()
    if forced in ("always", "1", "yes"):
        return True
    if forced in ("never", "0", "no"):
        return False
    if "NO_COLOR" in os.environ or os.environ.get("TERM") == "dumb":
        return False
    stream = stream or sys.stderr
    try:
        return stream.isatty()
    except (AttributeError, ValueError):
        return False


def colourize(text: str, stream=None) -> str:
    """``text`` with its ``error:``/``warning:``/``note:`` marks coloured,
    if colour is wanted on ``stream``."""
    if not use_colour(stream):
        return text
    return _SEVERITY.sub(lambda m: f"{_COLOURS[m.group(1)]}{m.group(0)}{_RESET}", text)


def trace_command(argv: Sequence[str]) -> None:
    """With ``--verbose``: show the command about to run."""
    if VERBOSE:
        sys.stderr.write("pyrosgen: $ " + " ".join(shlex.quote(str(a)) for a in argv) + "\n")
        sys.stderr.flush()


def trace_result(argv: Sequence[str], returncode: int, seconds: float) -> None:
    """With ``--verbose``: show how the command ended."""
    if VERBOSE:
        name = os.path.basename(str(argv[0])) if argv else "?"
        sys.stderr.write(f"pyrosgen:   {name}: exit {returncode}, {seconds:.2f} s\n")
        sys.stderr.flush()
