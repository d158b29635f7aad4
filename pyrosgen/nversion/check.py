"""The comparison of the proved model text with the second reading of the
model file (N-version, DESIGN.md section 7): one call for ``pyrosgen
generate`` and one for ``pyrosgen verify --model``."""

from __future__ import annotations

from pathlib import Path

import yaml

# The one pyrosgen import: the error family (exit code 2), which knows
# nothing of the model.
from pyrosgen.errors import DetailedFailure
from pyrosgen.nversion.msgs import STANDARD_ROOT, ReadingError
from pyrosgen.nversion.reader import model_text

__all__ = ["NVersionMismatch", "check_model_file", "differing_lines"]


class NVersionMismatch(DetailedFailure):
    """The model Coq proved things about is not the model file as the
    second, independent reading understands it (exit code 2: the two
    readings of the model disagree, so the front end, the emitter or the
    second reading is wrong)."""


def differing_lines(expected: str, proved: str, limit: int = 8) -> list[str]:
    """One line per item where the two texts differ (at most ``limit``,
    then how many more); empty when they are equal."""
    if expected == proved:
        return []
    exp, got = expected.splitlines(), proved.splitlines()
    diffs = []
    for i in range(max(len(exp), len(got))):
        a = exp[i] if i < len(exp) else "(nothing)"
        b = got[i] if i < len(got) else "(nothing)"
        if a != b:
            diffs.append(f"  item {i + 1}: the model file read independently says {a!r}; "
                         f"the proved model says {b!r}")
    return diffs[:limit] + ([f"  ... {len(diffs) - limit} more"] if len(diffs) > limit else [])


def check_model_file(path, proved_text: str, proved_diagram: str | None = None, *, vfile: str,
                     standard_root: Path = STANDARD_ROOT) -> None:
    """Raise :class:`NVersionMismatch` unless ``proved_text`` (the model
    text Coq printed from the model term of ``vfile``) is, byte for byte,
    the text of the model file at ``path`` as this package reads it,
    without the front end.  ``proved_diagram``, the diagram text Coq
    printed for a block-diagram controller (``None`` for none), is not
    compared yet: the second reading covers the model text only."""
    name = Path(path).name
    try:
        expected = model_text(path, standard_root=standard_root)
    except (ReadingError, OSError, UnicodeError, yaml.YAMLError, KeyError, TypeError, AttributeError,
            ValueError) as exc:
        detail = f"{type(exc).__name__}: {exc}" if not isinstance(exc, ReadingError) else str(exc)
        raise NVersionMismatch(
            f"the two readings of the model disagree: the second, independent reading of {name} "
            f"cannot read it", [f"  {detail}"]) from None
    lines = differing_lines(expected, proved_text)
    if lines:
        n = sum(1 for a, b in _pairs(expected, proved_text) if a != b)
        raise NVersionMismatch(
            f"the two readings of the model disagree: the model proved in {vfile} is not {name} as read "
            f"independently of the front end ({n} differing items)", lines)


def _pairs(a: str, b: str):
    x, y = a.splitlines(), b.splitlines()
    for i in range(max(len(x), len(y))):
        yield (x[i] if i < len(x) else None), (y[i] if i < len(y) else None)
