"""The DDC certificate written next to the generated glue (``CERTIFICATE.md``).

It lists, for an auditor: the node, each relation (source field, destination
field, type), the C lines that implement it, the Coq theorem that covers it
and that it was checked, the printed assumptions, the Frama-C result when
``--wp`` ran, tool versions, and SHA-256 digests of the model, the ``.v``
file and the C files.  Rendered from ``templates/CERTIFICATE.md.j2``.

The certificate is deterministic (no dates, no timings), so regenerating an
unchanged node leaves it untouched.
"""

from __future__ import annotations

import hashlib
import re
import shutil
import subprocess
from pathlib import Path

from pyrosgen.render import render

from pyrosgen.frontend.model import NodeModel



def sha256_file(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 16), b""):
            h.update(chunk)
    return h.hexdigest()


def tool_version(argv: list[str]) -> str:
    """The first line a tool prints about its version, or ``not found``."""
    if shutil.which(argv[0]) is None:
        return "not found"
    try:
        r = subprocess.run(argv, capture_output=True, text=True, timeout=30, check=False)
    except (OSError, subprocess.TimeoutExpired):
        return "not runnable"
    text = (r.stdout or r.stderr).strip().splitlines()
    return text[0].strip() if text else "unknown"


def tool_versions() -> list[tuple[str, str]]:
    return [
        ("coqc", tool_version(["coqc", "--version"]).replace("The Coq Proof Assistant, ", "")),
        ("ocamlopt", tool_version(["ocamlopt", "-version"])),
        ("gcc", tool_version(["gcc", "--version"])),
        ("frama-c", tool_version(["frama-c", "-version"])),
    ]


def _function_spans(c_text: str) -> dict[str, tuple[int, int]]:
    """Line spans (1-based, inclusive) of the function definitions in the
    printed C: a line ``<type> name(...)`` followed by ``{`` ... ``}``."""
    lines = c_text.splitlines()
    spans: dict[str, tuple[int, int]] = {}
    head = re.compile(r"^[A-Za-z_][A-Za-z0-9_ ]*?\b([A-Za-z_][A-Za-z0-9_]*)\(.*\)$")
    i = 0
    while i < len(lines):
        m = head.match(lines[i])
        if m and i + 1 < len(lines) and lines[i + 1] == "{":
            j = i + 2
            while j < len(lines) and lines[j] != "}":
                j += 1
            spans[m.group(1)] = (i + 1, j + 1)
            i = j
        i += 1
    return spans


def _copy_lines(lines: list[str], span: tuple[int, int], dst: str) -> list[tuple[int, str]]:
    """The two lines of the relation's copy into ``dst`` inside ``span``:
    ``_t = src;`` then ``dst = _t;`` (the last such assignment: an output
    glue first zeroes every field, then copies the related ones)."""
    first, last = span
    for n in range(last, first, -1):
        text = lines[n - 1].strip()
        if text.startswith(dst + " = _t_"):
            prev = lines[n - 2].strip()
            return [(n - 1, prev), (n, text)]
    raise ValueError(f"certificate: no copy into {dst} in lines {first}-{last}")


def render_certificate(model: NodeModel, *, node_v: Path, glue_c: Path, types_h: Path,
                       theorem: str, theorems: list[str], ddc: bool, assumptions: str,
                       wp: object = None) -> str:
    """The text of ``CERTIFICATE.md`` for the files just printed."""
    c_text = glue_c.read_text(encoding="utf-8")
    lines = c_text.splitlines()
    spans = _function_spans(c_text)
    uvar = model.controller.inputs.var_name
    yvar = model.controller.outputs.var_name
    inputs = []
    for r in model.input_relations:
        cb = spans[r.topic.callback]
        inputs.append({
            "src": f"{r.topic.name} {r.path}",
            "dst": f"{uvar}.{r.input_field}",
            "type": r.path.prim,
            "callback": r.topic.callback,
            "cb_first": cb[0],
            "cb_last": cb[1],
            "lines": _copy_lines(lines, spans["input_glue"], f"{uvar}.{r.input_field}"),
        })
    outputs = []
    for r in model.output_relations:
        dst = r.path.c_access("(*command)")
        outputs.append({
            "src": f"{yvar}.{r.output_field}",
            "dst": f"{r.topic.name} {r.path}",
            "type": r.path.prim,
            "lines": _copy_lines(lines, spans[r.topic.output_glue], dst),
        })
    wp_ctx = None
    if wp is not None:
        wp_ctx = {
            "proved": getattr(wp, "proved", "?"),
            "total": getattr(wp, "total", "?"),
            "prover": getattr(wp, "prover", "") or "",
        }
    hashes = [
        (model.source.name, sha256_file(model.source)),
        (node_v.name, sha256_file(node_v)),
        (types_h.name, sha256_file(types_h)),
        (glue_c.name, sha256_file(glue_c)),
    ]
    return render("CERTIFICATE.md.j2",
        source=model.source.name,
        model=model,
        node_v=node_v.name,
        glue_c=glue_c.name,
        types_h=types_h.name,
        theorem=theorem,
        theorems=theorems,
        ddc=ddc,
        assumptions=assumptions.strip(),
        inputs=inputs,
        outputs=outputs,
        wp=wp_ctx,
        tools=tool_versions(),
        hashes=hashes,
    )
