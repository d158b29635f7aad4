"""``pyrosgen diagram``: a picture of a node's data flow.

The picture follows the paper's Figures 4 and 9: each subscribed topic feeds
its callback, which copies what the node reads of the message into a
global message variable (the edge says how many fields); the
input glue copies the related fields into ``Controller_U`` (one edge per
input relation, labelled with the message field path and its type; a
direct relation, DESIGN.md rule 4.16, is drawn from the callback, which
copies it straight into ``Controller_U``);
``<Controller>_step`` turns ``Controller_U`` into ``Controller_Y``; each
``output_glue_<c>`` copies ``Controller_Y`` fields into the message it
publishes (one edge per output relation, labelled with the destination
field path and its type).  Clusters separate the ROS side, the generated
glue (the part the Coq proofs are about) and the controller.

Timing (DESIGN.md rules 4.12, 4.13) is drawn too: a subscribed topic shows
its ``timeout_ms`` and ``on_timeout``; an input relation from a topic with
a timeout says what its input gets while the topic is stale (its fallback,
or ``hold``); a derived input (``is_new``, ``received``, ``age_ms``) is a
dashed edge from the topic's callback, which records each receipt, to the
input it feeds; a published topic shows its ``header.stamp`` (``now``, or
the stamp of a subscribed topic's newest message, then also a dashed edge
from that topic's global to the output glue that copies it).

The DOT text comes from ``templates/diagram.dot.j2``; Graphviz's ``dot``
turns it into SVG, PNG or PDF.  Every text from the model reaches the DOT
text through :func:`dot_html`, whatever the front end already checked, and
graph, node, port and edge identifiers are generated here (``sub0``,
``f1``, ...), never taken from the model.  The DOT text depends only on the
model (and the model file's base name), so the same model gives
byte-identical DOT.
"""

from __future__ import annotations

import errno
import html
import os
import shutil
import stat
import subprocess
import tempfile
from pathlib import Path
from typing import Any


from pyrosgen.errors import ToolFailure, UserError, escape, show
from pyrosgen.render import render
from pyrosgen.frontend.model import DERIVED_PRIMS, NodeModel

__all__ = [
    "FORMATS",
    "DiagramError",
    "dot_html",
    "diagram_context",
    "render_dot",
    "output_format",
    "find_dot",
    "run_dot",
    "write_atomic",
    "write_diagram",
]

TEMPLATE = "diagram.dot.j2"

#: Output formats, and the file suffixes that select them.
FORMATS: tuple[str, ...] = ("svg", "png", "pdf", "dot")
_SUFFIXES = {".svg": "svg", ".png": "png", ".pdf": "pdf", ".dot": "dot", ".gv": "dot"}

#: Seconds ``dot`` may take (a node with thousands of relations takes a few).
DOT_TIMEOUT = 600


class DiagramError(ToolFailure):
    """Graphviz is missing or failed (exit code 2)."""


def dot_html(value: object) -> str:
    """``value`` as text inside a Graphviz HTML-like label (also safe inside
    a double-quoted DOT string).

    Non-printable and non-ASCII characters become visible escapes
    (:func:`pyrosgen.errors.escape`), backslashes are doubled (Graphviz
    expands ``\\N``, ``\\G``, ... even in HTML-like labels, and after
    decoding character references, so ``&#92;`` would not do), and
    ``& < > " '`` become character references.
    """
    text = escape(str(value), keep_quotes=True).replace("\\", "\\\\")
    return html.escape(text, quote=True)


def _kept_count(model: NodeModel, topic) -> int | None:
    """How many scalar fields the callback of subscribed ``topic`` copies
    into the topic's global (:meth:`NodeModel.read_leaves`: those of its
    relations that are not direct, rule 4.16, and of a stamp copied from
    it), ``None`` if unknown."""
    try:
        return len(model.read_leaves(topic))
    except (KeyError, ValueError):
        return None


def _rate(period_ms: int) -> str:
    hz = 1000 / period_ms if period_ms > 0 else 0
    return f"{hz:g}"


def _rows(relations) -> list[tuple[Any, int]]:
    """The relations as the model writes them: the element relations a
    whole-array row expands into (rule 4.15, consecutive, with the same
    ``row`` and position) drawn as one edge; each with how many relations
    it stands for."""
    out: list[list] = []
    for r in relations:
        if r.row is not None and out and out[-1][0].row == r.row and out[-1][0].pos == r.pos \
                and out[-1][0].topic.name == r.topic.name:
            out[-1][1] += 1
        else:
            out.append([r, 1])
    return [(r, n) for r, n in out]


def _stale(r) -> str | None:
    """What input relation ``r`` gives its input while its topic is stale
    (rule 4.12): its fallback's text, ``hold``, or ``None`` when its topic
    has no timeout."""
    if r.topic.timeout_ms is None:
        return None
    return "hold" if r.fallback is None else (r.fallback.text or str(r.fallback.n))


def _stamp(t) -> str | None:
    """The ``header.stamp`` of published topic ``t`` (rule 4.13)."""
    if not t.stamped:
        return None
    return "now (the cycle's ROS time)" if t.stamp_from is None else f"from {t.stamp_from}"


def _label(text: str, index: int | None, row) -> str:
    """An edge's field: ``ranges``, ``ranges[540]``, and the element of a
    controller array a relation names (rule 4.15): ``ranges[540] (element 0)``."""
    return text if index is None or row is not None else f"{text} (element {index})"


def diagram_context(model: NodeModel) -> dict[str, Any]:
    """The template context for ``model`` (see the template's header)."""
    ctrl = model.controller

    def io(node_id: str, s) -> dict[str, Any]:
        return {
            "id": node_id,
            "var": s.var_name,
            "struct": s.struct_name,
            "fields": [{"port": f"f{i}", "name": f.name, "prim": f.type_text} for i, f in enumerate(s.fields)],
        }

    u = io("ctrl_u", ctrl.inputs)
    y = io("ctrl_y", ctrl.outputs)
    u_port = {f.name: f"f{i}" for i, f in enumerate(ctrl.inputs.fields)}
    y_port = {f.name: f"f{i}" for i, f in enumerate(ctrl.outputs.fields)}

    subs = []
    var_of: dict[str, str] = {}
    cb_of: dict[str, str] = {}
    for i, t in enumerate(model.subscribed):
        subs.append(
            {
                "id": f"sub{i}",
                "cb_id": f"cb{i}",
                "var_id": f"msg{i}",
                "name": t.name,
                "type": t.msg_type,
                "queue": t.queue_size,
                "callback": t.callback,
                "var": t.msg_var,
                "struct": t.msg_struct,
                "nfields": _kept_count(model, t),
                # rule 4.12: None without a timeout
                "timeout_ms": t.timeout_ms,
                "on_timeout": t.on_timeout,
            }
        )
        var_of.setdefault(t.name, f"msg{i}")
        cb_of.setdefault(t.name, f"cb{i}")

    pubs = []
    glue_of: dict[str, str] = {}
    for i, t in enumerate(model.published):
        pubs.append(
            {
                "id": f"pub{i}",
                "og_id": f"og{i}",
                "name": t.name,
                "type": t.msg_type,
                "queue": t.queue_size,
                "glue": t.output_glue,
                "cmd": t.cmd_var,
                "publish": t.publish_fn,
                # constant strings (rule 4.14), shown on the topic
                "strings": [{"path": c.path_text, "value": c.value} for c in t.strings],
                # rule 4.13: None when not stamped
                "stamp": _stamp(t),
            }
        )
        glue_of.setdefault(t.name, f"og{i}")
    # a stamp copied from a subscribed topic: from its global (where its
    # callback keeps the stamp) to the output glue that copies it
    stamp_edges = [
        {"id": f"stamp{k}", "tail": var_of[t.stamp_from], "head": glue_of[t.name]}
        for k, t in enumerate(t for t in model.published if t.stamped and t.stamp_from is not None)
        if t.stamp_from in var_of
    ]

    in_rels = []
    for i, (r, n) in enumerate(_rows(model.input_relations)):
        if r.topic.name not in var_of or r.input_field not in u_port:
            raise ValueError(f"input relation {i} names an unknown topic or input field")
        in_rels.append(
            {
                "id": f"in_rel{i}",
                # a direct relation (rule 4.16) is copied by the callback,
                # from the message straight into the inputs; any other by
                # input_glue, from the topic's global
                "tail": cb_of[r.topic.name] if model.is_direct(r) else var_of[r.topic.name],
                "head": u["id"],
                "port": u_port[r.input_field],
                # as the model writes it: ranges[540], ranges (length), a
                # whole array (ranges), an element of a controller array
                "path": _label(r.row[0] if r.row else r.field_text, r.input_index, r.row),
                "prim": f"{r.path.prim}[{n}]" if r.row else r.path.prim,
                "stale": _stale(r),
            }
        )
    # derived inputs (rule 4.12): facts about a topic's messages, which its
    # callback records (receipt time, flags) and input_glue turns into the
    # input's value
    derived = []
    for i, r in enumerate(model.derived_relations):
        if r.topic.name not in cb_of or r.input_field not in u_port:
            raise ValueError(f"derived input {i} names an unknown topic or input field")
        derived.append(
            {
                "id": f"derived{i}",
                "tail": cb_of[r.topic.name],
                "head": u["id"],
                "port": u_port[r.input_field],
                "kind": r.kind,
                "prim": DERIVED_PRIMS[r.kind],
            }
        )
    out_rels = []
    for i, (r, n) in enumerate(_rows(model.output_relations)):
        if r.topic.name not in glue_of or r.output_field not in y_port:
            raise ValueError(f"output relation {i} names an unknown topic or output field")
        out_rels.append(
            {
                "id": f"out_rel{i}",
                "tail": y["id"],
                "port": y_port[r.output_field],
                "head": glue_of[r.topic.name],
                # as the model writes it: data[3], data (length), a whole array
                "path": _label(r.row[1] if r.row else r.field_text, r.output_index, r.row),
                "prim": f"{r.path.prim}[{n}]" if r.row else r.path.prim,
            }
        )

    return {
        "source": Path(model.source).name,
        "node": {"name": model.name, "period_ms": model.period_ms, "rate_hz": _rate(model.period_ms)},
        "subs": subs,
        "ctrl": {"step_id": "step", "step": ctrl.step_fn, "u": u, "y": y},
        "pubs": pubs,
        "in_rels": in_rels,
        "derived": derived,
        "out_rels": out_rels,
        "stamp_edges": stamp_edges,
    }


def render_dot(model: NodeModel) -> str:
    """The DOT text of the diagram of ``model``."""
    # finalize escapes every {{ expression }}: nothing from the model can be
    # printed raw, and the identifiers generated here pass through unchanged.
    return render(TEMPLATE, finalize=dot_html, **diagram_context(model))


def output_format(output: str | os.PathLike[str], override: str | None = None) -> str:
    """The output format: ``override`` if given, else from the suffix of
    ``output``.  Raises ``ValueError`` when neither says."""
    if override is not None:
        if override not in FORMATS:
            raise ValueError(f"unknown format {override!r}; use one of {', '.join(FORMATS)}")
        return override
    suffix = Path(output).suffix.lower()
    if suffix not in _SUFFIXES:
        raise ValueError(
            f"cannot tell the output format from the name {escape(str(output))!r}: "
            f"use a .svg, .png, .pdf or .dot suffix, or --format {{{','.join(FORMATS)}}}"
        )
    return _SUFFIXES[suffix]


def find_dot() -> str:
    """The path of Graphviz's ``dot`` (``$PYROSGEN_DOT`` or on ``PATH``)."""
    exe = os.environ.get("PYROSGEN_DOT") or shutil.which("dot")
    if not exe or not (os.path.isfile(exe) and os.access(exe, os.X_OK)):
        raise DiagramError(
            "Graphviz's 'dot' program was not found on PATH; install the Debian package "
            "graphviz (`make deps` does) or choose the .dot output format"
        )
    return exe


def run_dot(dot_text: str, fmt: str, exe: str | None = None) -> bytes:
    """Run ``dot -T<fmt>`` on ``dot_text``; return its output."""
    exe = exe or find_dot()
    try:
        proc = subprocess.run(
            [exe, f"-T{fmt}"],
            input=dot_text.encode("utf-8"),
            capture_output=True,
            check=False,
            timeout=DOT_TIMEOUT,
        )
    except subprocess.TimeoutExpired as exc:
        raise DiagramError(f"'dot -T{fmt}' did not finish in {DOT_TIMEOUT} s") from exc
    except OSError as exc:
        raise DiagramError(f"cannot run {exe}: {exc.strerror or exc}") from exc
    if proc.returncode != 0 or not proc.stdout:
        detail = proc.stderr.decode("utf-8", "replace").strip() or f"exit code {proc.returncode}"
        raise DiagramError(f"'dot -T{fmt}' failed: {detail}")
    return proc.stdout


class DiagramOutputError(UserError):
    """The diagram's output path cannot be written as asked (exit 1)."""


def _kind(mode: int) -> str:
    return ("a symbolic link" if stat.S_ISLNK(mode) else "a directory" if stat.S_ISDIR(mode)
            else "a FIFO" if stat.S_ISFIFO(mode) else "a socket" if stat.S_ISSOCK(mode)
            else "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) else "not a regular file")


def write_atomic(path: Path, data: bytes) -> bool:
    """Write ``data`` to ``path`` through a temporary file in the same
    folder and a rename, so that ``path`` is never seen half written and a
    failure leaves it as it was.

    ``path`` must be a regular file or not exist: a symbolic link, a FIFO,
    a device, a socket or a directory there is refused (it would otherwise
    be replaced by a regular file), and so is a missing folder (it is not
    created).  A replaced file keeps its permission bits.  Leaves ``path``
    untouched when it already holds ``data``; returns whether it wrote."""
    path = Path(path)
    shown = escape(str(path))
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        st = None
    except OSError as exc:
        if exc.errno == errno.ENOTDIR:
            st = None  # reported below, with the folder
        else:
            raise DiagramOutputError(f"{shown}: {exc.strerror or exc}") from None
    if st is not None and not stat.S_ISREG(st.st_mode):
        raise DiagramOutputError(f"{shown}: exists and is {_kind(st.st_mode)}, not a regular file; "
                                 "pyrosgen diagram writes or replaces only regular files")
    folder = path.parent
    try:
        folder_st = os.stat(folder)
    except FileNotFoundError:
        raise DiagramOutputError(f"{escape(str(folder))}: the output folder does not exist "
                                 "(pyrosgen diagram does not create it)") from None
    except OSError as exc:
        if exc.errno != errno.ENOTDIR:
            raise DiagramOutputError(f"{escape(str(folder))}: {exc.strerror or exc}") from None
        folder_st = None
    if folder_st is None or not stat.S_ISDIR(folder_st.st_mode):
        raise DiagramOutputError(f"{escape(str(folder))}: not a folder, so it cannot hold the output file")
    if st is not None and st.st_size == len(data):
        try:
            with open(path, "rb") as fh:
                if fh.read(len(data) + 1) == data:
                    return False
        except OSError:
            pass
    if st is not None:
        mode = stat.S_IMODE(st.st_mode)
    else:
        umask = os.umask(0)
        os.umask(umask)
        mode = 0o666 & ~umask
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, mode)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
    return True


def write_diagram(model: NodeModel, output: str | os.PathLike[str], fmt: str) -> bool:
    """Draw ``model`` into ``output`` in format ``fmt`` (one of
    :data:`FORMATS`); nothing is written if anything fails."""
    text = os.fspath(output)
    if not text or text.endswith(("/", os.sep)) or os.path.basename(text) in (".", ".."):
        # Path() would drop a final "/": "out.svg/" names a folder, not a file
        raise DiagramOutputError(f"{show(text)} names a folder, not a file; give a file name")
    dot_text = render_dot(model)
    data = dot_text.encode("utf-8") if fmt == "dot" else run_dot(dot_text, fmt)
    return write_atomic(Path(text), data)
