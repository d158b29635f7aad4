"""The comparison of the proved model text with the second reading of the
model file (N-version, DESIGN.md section 7): one call for ``pyrosgen
generate`` and one for ``pyrosgen verify --model``."""

from __future__ import annotations

from pathlib import Path

# The one pyrosgen import: the error family (exit code 2), which knows
# nothing of the model.
from pyrosgen.errors import DetailedFailure
from pyrosgen.nversion.msgs import STANDARD_ROOT, ReadingError
from pyrosgen.nversion.diagram import diagram_lines, has_diagram
from pyrosgen.nversion.reader import model_lines, read_yaml

__all__ = ["NVersionMismatch", "check_model_file", "differing_lines"]


class NVersionMismatch(DetailedFailure):
    """The model Coq proved things about is not the model file as the
    second, independent reading understands it (exit code 2: the two
    readings of the model disagree, so the front end, the emitter or the
    second reading is wrong)."""


def differing_lines(expected: str, proved: str, limit: int = 8, *, at=(), file: str = "",
                    what: str = "the proved model") -> list[str]:
    """One line per item where the two texts differ (at most ``limit``,
    then how many more); empty when they are equal.  ``at`` gives, item by
    item, the line of the model file it comes from (``None``: none of its
    own; else ``(line, column)``), shown as ``file:line:column``."""
    if expected == proved:
        return []
    exp, got = expected.splitlines(), proved.splitlines()
    at = list(at)
    diffs = []
    for i in range(max(len(exp), len(got))):
        a = exp[i] if i < len(exp) else "(nothing)"
        b = got[i] if i < len(got) else "(nothing)"
        if a != b:
            where = f" ({file}:{at[i][0]}:{at[i][1]})" if i < len(at) and at[i] is not None else ""
            diffs.append(f"  item {i + 1}{where}: the model file read independently says {a!r}; "
                         f"{what} says {b!r}")
    return diffs[:limit] + ([f"  ... {len(diffs) - limit} more"] if len(diffs) > limit else [])


def check_model_file(path, proved_text: str, proved_diagram: str | None = None, *, vfile: str,
                     standard_root: Path = STANDARD_ROOT) -> None:
    """Raise :class:`NVersionMismatch` unless ``proved_text`` (the model
    text Coq printed from the model term of ``vfile``) is, byte for byte,
    the text of the model file at ``path`` as this package reads it,
    without the front end, and ``proved_diagram`` (the diagram text Coq
    printed for a block-diagram controller, ``None`` when ``vfile`` proves
    none) is the file's block diagram as this package reads it."""
    name = Path(path).name
    try:
        doc = read_yaml(Path(path))
        lines = model_lines(path, standard_root=standard_root, doc=doc)
        expected = "".join(line + "\n" for line in lines)
        dlines = diagram_lines(path, doc=doc) if has_diagram(path, doc=doc) else None
        diagram = "".join(line + "\n" for line in dlines) if dlines is not None else None
    except Exception as exc:  # noqa: BLE001 - whatever stops the second reading is a disagreement (exit 2)
        detail = f"{type(exc).__name__}: {exc}" if not isinstance(exc, ReadingError) else str(exc)
        raise NVersionMismatch(
            f"the two readings of the model disagree: the second, independent reading of {name} "
            f"cannot read it", [f"  {detail}"]) from None
    lines = differing_lines(expected, proved_text, at=[line.at for line in lines], file=str(path))
    if lines:
        raise NVersionMismatch(
            f"the two readings of the model disagree: the model proved in {vfile} is not {name} as read "
            f"independently of the front end ({_count(expected, proved_text)} differing items)", lines)
    if (diagram is None) != (proved_diagram is None):
        raise NVersionMismatch(
            f"the two readings of the model disagree: {name} read independently "
            + ("has a block diagram, but " + vfile + " proves none" if diagram is not None
               else "has no block diagram, but " + vfile + " proves one"), [])
    lines = differing_lines(diagram or "", proved_diagram or "", at=[line.at for line in dlines or ()],
                            file=str(path), what="the proved diagram")
    if lines:
        raise NVersionMismatch(
            f"the two readings of the model disagree: the controller diagram proved in {vfile} is not the "
            f"diagram of {name} as read independently of the front end "
            f"({_count(diagram or '', proved_diagram or '')} differing items)", lines)


def _count(a: str, b: str) -> int:
    return sum(1 for x, y in _pairs(a, b) if x != y)


def _pairs(a: str, b: str):
    x, y = a.splitlines(), b.splitlines()
    for i in range(max(len(x), len(y))):
        yield (x[i] if i < len(x) else None), (y[i] if i < len(y) else None)
