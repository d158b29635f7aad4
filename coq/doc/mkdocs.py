#!/usr/bin/env python3
"""Build the HTML documentation of the ROSGen Coq library (``make docs``).

Writes, into ``--out`` (default ``build/docs``):

- ``coq/``: coqdoc's pages for every module of ``_CoqProject``, in its
  order, with links between identifiers (from the ``.glob`` files of the
  build), a table of contents (``coq/toc.html``) and coqdoc's index of
  identifiers (``coq/index.html``); each page gets a navigation bar;
- ``index.html``: the library's front page: its layout (the modules by
  layer folder, one paragraph per module, taken from the module's header
  comment) and its main theorems (``theorems.yaml``: ``Main.name``, the
  restatement in ``theories/Main.v``, and optionally ``proof``, the library
  lemma it applies), each linked to its coqdoc anchor
  (``coq/ROSGen.layer.Module.html#name``) when, and only when, the module is
  in ``_CoqProject``, the statement is in the module's source (outside
  comments) and coqdoc made that anchor; otherwise the theorem is listed as
  "not yet in the library".  A module is named in ``theorems.yaml`` by its
  base name (``Glueproof``) or its path under the library (``glue.Glueproof``);
  base names are unique in the library;
- with ``--example MODEL``, the data-flow diagram of that node
  (``pyrosgen diagram``), shown on the front page.

The new tree is built next to the old one and swapped in at the end, so an
interrupted run leaves the previous documentation in place.

Exit codes: 0 success, 2 missing build products or a failing tool.
Needs jinja2 and pyyaml (run it with the project's virtual environment).
"""

from __future__ import annotations

import argparse
import html
import html.parser
import os
import re
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import jinja2
import yaml

HERE = Path(__file__).resolve().parent
COQLIB_URL = "https://coq.inria.fr/doc/V8.16.1/stdlib/"
TITLE = "ROSGen: the Coq library of pyrosgen"

_STATEMENT = re.compile(
    r"^[ \t]*(?:(?:Local|Global|Polymorphic|Program)\s+)*"
    r"(?P<kind>Theorem|Lemma|Corollary|Proposition|Fact|Remark|Example|Definition|Fixpoint|Inductive)"
    r"\s+(?P<name>[A-Za-z_][A-Za-z0-9_']*)",
    re.M,
)


class DocsError(Exception):
    """A problem that stops the documentation build."""


# --------------------------------------------------------------------------
# _CoqProject


@dataclass(frozen=True)
class Project:
    """The library as ``_CoqProject`` lists it."""

    root: Path                 #: the folder of _CoqProject
    phys: str                  #: physical folder of the library (theories)
    logical: str               #: its logical name (ROSGen)
    files: tuple[str, ...]     #: .v files, in order, relative to root
    layers: tuple[tuple[str, str], ...] = ()  #: (folder, description) from "# folder: ..." comments

    def module(self, vfile: str) -> str:
        """``theories/lib/Foo.v`` -> ``ROSGen.lib.Foo``."""
        rel = Path(vfile).relative_to(self.phys).with_suffix("")
        return ".".join((self.logical, *rel.parts))

    def layer(self, vfile: str) -> str:
        """``theories/lib/Foo.v`` -> ``lib``; ``theories/Foo.v`` -> ``""``."""
        return "/".join(Path(vfile).relative_to(self.phys).parent.parts)

    def resolve(self, name: str) -> str | None:
        """The module of ``_CoqProject`` that ``name`` designates: the path
        under the library (``glue.Glueproof``) or a unique base name
        (``Glueproof``); ``None`` if there is none or several."""
        modules = [self.module(v) for v in self.files]
        full = f"{self.logical}.{name}"
        if full in modules:
            return full
        found = [m for m in modules if m.endswith("." + name)]
        return found[0] if len(found) == 1 else None


def read_project(root: Path) -> Project:
    """Parse ``root/_CoqProject`` (``-R`` mapping and ordered file list)."""
    path = root / "_CoqProject"
    try:
        lines = path.read_text().splitlines()
    except OSError as exc:
        raise DocsError(f"cannot read {path}: {exc.strerror}") from exc
    words = [w for line in lines if not line.lstrip().startswith("#") for w in line.split()]
    # "# lib: general-purpose definitions" describes the folder theories/lib;
    # "# top: ..." the files directly in theories.
    layers = tuple(
        ("" if m.group(1) == "top" else m.group(1), m.group(2).strip())
        for m in (re.match(r"^#\s*([A-Za-z0-9_]+):\s*(.+)$", line.strip()) for line in lines)
        if m
    )
    phys = logical = None
    files: list[str] = []
    i = 0
    while i < len(words):
        w = words[i]
        if w in ("-R", "-Q") and i + 2 < len(words):
            phys, logical = words[i + 1], words[i + 2]
            i += 3
        elif w == "-arg" and i + 1 < len(words):
            i += 2
        elif w.endswith(".v"):
            files.append(w)
            i += 1
        else:
            i += 1
    if phys is None or not files:
        raise DocsError(f"{path}: no -R mapping or no .v file")
    return Project(root, phys.rstrip("/"), logical,
                   tuple(f for f in files if f.startswith(phys.rstrip("/") + "/")), layers)


# --------------------------------------------------------------------------
# Coq sources: comments, statements, coqdoc markup


@dataclass(frozen=True)
class DocComment:
    start: int
    end: int
    body: str       #: the text between "(**" and "*)"


def _skip_string(text: str, i: int) -> int:
    """Index after the Coq string starting at ``text[i] == '"'``."""
    k = i + 1
    while True:
        j = text.find('"', k)
        if j < 0:
            return len(text)
        if text.startswith('""', j):
            k = j + 2
            continue
        return j + 1


def _skip_comment(text: str, i: int) -> int:
    """Index after the (nested) comment starting at ``text[i:i+2] == '(*'``."""
    depth, k, n = 0, i, len(text)
    while k < n:
        if text.startswith("(*", k):
            depth += 1
            k += 2
        elif text.startswith("*)", k):
            depth -= 1
            k += 2
            if depth == 0:
                return k
        elif text[k] == '"':
            k = _skip_string(text, k)
        else:
            k += 1
    return n


def scan(text: str) -> tuple[str, list[DocComment]]:
    """``text`` with every comment blanked (newlines kept, so positions
    agree), and its documentation comments ``(** ... *)``."""
    out = list(text)
    docs: list[DocComment] = []
    i, n = 0, len(text)
    while i < n:
        if text[i] == '"':
            i = _skip_string(text, i)
        elif text.startswith("(*", i):
            j = _skip_comment(text, i)
            if text.startswith("(**", i) and not text.startswith("(**)", i):
                docs.append(DocComment(i, j, text[i + 3 : max(i + 3, j - 2)]))
            for k in range(i, j):
                if out[k] != "\n":
                    out[k] = " "
            i = j
        else:
            i += 1
    return "".join(out), docs


def statements(code: str) -> dict[str, int]:
    """Name -> position of every statement/definition in comment-free ``code``."""
    found: dict[str, int] = {}
    for m in _STATEMENT.finditer(code):
        found.setdefault(m.group("name"), m.start("kind"))
    return found


def segments(text: str) -> list[dict]:
    """Split coqdoc text into plain and ``[code]`` segments (brackets nest;
    an opening bracket that is never closed is plain text)."""
    segs: list[dict] = []
    buf, depth, opened = "", 0, 0
    for i, ch in enumerate(text):
        if depth == 0 and ch == "[":
            if buf:
                segs.append({"code": False, "text": buf})
            buf, depth, opened = "", 1, i
        elif depth > 0 and ch == "[":
            depth += 1
            buf += ch
        elif depth > 0 and ch == "]":
            depth -= 1
            if depth == 0:
                segs.append({"code": True, "text": buf})
                buf = ""
            else:
                buf += ch
        else:
            buf += ch
    if depth > 0:
        rest = segments(text[opened + 1 :])
        if rest and not rest[0]["code"]:
            rest[0] = {"code": False, "text": "[" + rest[0]["text"]}
        else:
            rest.insert(0, {"code": False, "text": "["})
        if segs and not segs[-1]["code"]:
            segs[-1] = {"code": False, "text": segs[-1]["text"] + rest.pop(0)["text"]}
        return segs + rest
    if buf:
        segs.append({"code": False, "text": buf})
    return segs


def blocks(body: str, first_only: bool = False) -> list[dict]:
    """The paragraphs and ``- `` lists of a coqdoc comment, as
    ``{"kind": "p", "segs": [...]}`` and ``{"kind": "ul", "items": [segs, ...]}``.
    Stops at a verbatim block (``<<``) or a heading; with ``first_only``, at
    the first blank line after some text."""
    out: list[dict] = []
    cur: list[str] | None = None     # lines of the current paragraph or item
    cur_kind = None
    item_indent = 0

    def flush():
        nonlocal cur, cur_kind
        if cur:
            text = " ".join(cur)
            if cur_kind == "item":
                if not out or out[-1]["kind"] != "ul":
                    out.append({"kind": "ul", "items": []})
                out[-1]["items"].append(segments(text))
            else:
                out.append({"kind": "p", "segs": segments(text)})
        cur, cur_kind = None, None

    for line in body.splitlines():
        s = line.strip()
        indent = len(line) - len(line.lstrip())
        if s.startswith("<<") or (s.startswith("*") and not s.startswith("*)")):
            break
        if not s:
            if first_only and (out or cur):
                break
            flush()
            continue
        if s.startswith("- "):
            flush()
            cur, cur_kind, item_indent = [s[2:].strip()], "item", indent
        elif cur_kind == "item" and indent > item_indent:
            cur.append(s)
        elif cur_kind == "p":
            cur.append(s)
        else:
            flush()
            cur, cur_kind = [s], "p"
    flush()
    return out


@dataclass
class Source:
    """What the documentation needs from one ``.v`` file."""

    module: str
    vfile: str
    title: str = ""
    summary: list[dict] = field(default_factory=list)
    statements: dict[str, int] = field(default_factory=dict)
    docs: list[DocComment] = field(default_factory=list)
    text: str = ""

    def doc_before(self, name: str) -> list[dict]:
        """The documentation comment right above statement ``name``."""
        pos = self.statements.get(name)
        if pos is None:
            return []
        for d in reversed(self.docs):
            if d.end <= pos:
                if self.text[d.end : pos].strip() == "" and not d.body.lstrip().startswith("*"):
                    return blocks(d.body)
                return []
        return []


def read_source(project: Project, vfile: str) -> Source:
    """Title, summary paragraph and statements of ``vfile``."""
    path = project.root / vfile
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise DocsError(f"cannot read {path}: {exc.strerror}") from exc
    code, docs = scan(text)
    src = Source(project.module(vfile), vfile, statements=statements(code), docs=docs, text=text)
    for d in docs:
        body = d.body.strip()
        if not src.title and body.startswith("*"):
            src.title = body.lstrip("*").strip()
        elif src.title and not body.startswith("*"):
            src.summary = blocks(d.body, first_only=True)
            break
    return src


# --------------------------------------------------------------------------
# HTML pages: anchors


class _Anchors(html.parser.HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.ids: set[str] = set()

    def handle_starttag(self, tag, attrs):
        for k, v in attrs:
            if k in ("id", "name") and v is not None:
                self.ids.add(v)


def anchors(path: Path) -> set[str]:
    """The ``id`` and ``name`` anchors of an HTML file (empty if missing)."""
    try:
        text = path.read_text(encoding="utf-8")
    except OSError:
        return set()
    p = _Anchors()
    p.feed(text)
    p.close()
    return p.ids


# --------------------------------------------------------------------------
# The build


def _env() -> jinja2.Environment:
    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(HERE)),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        autoescape=True,
    )


def check_built(project: Project) -> None:
    """Every module was compiled after its last change, and its ``.glob``
    is from that compilation (``.vo`` and ``.glob`` are written together at
    the end of a successful ``coqc``; a failed one leaves a newer, partial
    ``.glob`` next to the old ``.vo``)."""
    stale = []
    for v in project.files:
        vpath = project.root / v
        vo, glob = vpath.with_suffix(".vo"), vpath.with_suffix(".glob")
        try:
            t_v, t_vo, t_glob = (p.stat().st_mtime for p in (vpath, vo, glob))
        except OSError:
            stale.append(v)
            continue
        if t_vo < t_v or t_glob > t_vo + 1.0:
            stale.append(v)
    if stale:
        raise DocsError(
            f"no up-to-date .glob file for {', '.join(stale)}: build the library first (make -C coq build)"
        )


def run_coqdoc(project: Project, outdir: Path) -> None:
    """coqdoc over the whole library, into ``outdir``."""
    exe = shutil.which("coqdoc")
    if exe is None:
        raise DocsError("coqdoc not found on PATH (Debian package coq)")
    cmd = [
        exe, "--html", "--utf8", "--toc", "--interpolate",
        "-t", TITLE, "--coqlib_url", COQLIB_URL,
        "-R", project.phys, project.logical,
        "-d", str(outdir),
        *project.files,
    ]
    proc = subprocess.run(cmd, cwd=project.root, capture_output=True, text=True, check=False)
    # coqdoc echoes the document title on stdout; its warnings go to stderr.
    for line in proc.stderr.splitlines():
        if line.strip():
            print(f"docs: coqdoc: {line}", file=sys.stderr)
    if proc.returncode != 0:
        raise DocsError(f"coqdoc failed (exit code {proc.returncode})")


def add_navigation(outdir: Path) -> int:
    """Put the navigation bar into the (empty) header of every coqdoc page."""
    nav = _env().get_template("nav.html.j2").render().strip()
    n = 0
    for page in sorted(outdir.glob("*.html")):
        text = page.read_text(encoding="utf-8")
        new = text.replace('<div id="header">\n</div>', f'<div id="header">\n{nav}\n</div>', 1)
        if new != text:
            page.write_text(new, encoding="utf-8")
            n += 1
    return n


_LINK = re.compile(r"<a\b([^>]*)>(.*?)</a>", re.S)
_HREF = re.compile(r'\bhref="([^"]*)"')


def unlink_dangling(outdir: Path) -> int:
    """Replace every local link of the coqdoc pages whose file or anchor
    does not exist by its text; return how many were removed.

    coqdoc links some identifiers to anchors it never writes (binders in
    [match goal] patterns and notations, record constructors), so these
    links would lead nowhere."""
    pages = {p.name: p for p in outdir.glob("*.html")}
    ids = {name: anchors(p) for name, p in pages.items()}
    removed = 0
    for name, page in sorted(pages.items()):
        text = page.read_text(encoding="utf-8")

        def fix(m: re.Match) -> str:
            nonlocal removed
            attrs = m.group(1)
            href = _HREF.search(attrs)
            if href is None or "id=" in attrs:
                return m.group(0)
            target = href.group(1)
            if re.match(r"^[a-z][a-z0-9+.-]*:", target) or target.startswith("../"):
                return m.group(0)
            file, _, frag = target.partition("#")
            file = file or name
            if file in ids and (not frag or html.unescape(frag) in ids[file]):
                return m.group(0)
            removed += 1
            return m.group(2)

        new = _LINK.sub(fix, text)
        if new != text:
            page.write_text(new, encoding="utf-8")
    return removed


def assumptions_checked(project: Project) -> set[str]:
    """Theorems whose axioms ``make proofs`` checks: every ``Theorem`` of
    ``Main.v`` (``make -C coq check-assumptions``), as ``Main.name``."""
    mains = [v for v in project.files if Path(v).name == "Main.v"]
    if not mains:
        return set()
    try:
        code, _ = scan((project.root / mains[0]).read_text(encoding="utf-8"))
    except OSError:
        return set()
    return {f"Main.{n}" for n in re.findall(r"^Theorem\s+([A-Za-z_][A-Za-z0-9_']*)", code, re.M)}


def _link(project: Project, sources: dict[str, Source], coqhtml: Path,
          page_anchors: dict[str, set[str]], full: str) -> dict:
    """Where ``Module.name`` is: its link, or why it has none."""
    mod, _, name = full.rpartition(".")
    module = project.resolve(mod)
    src = sources.get(module) if module else None
    out = {"name": name, "module": mod, "full": full, "href": None, "reason": None, "src": src}
    if src is None:
        out["reason"] = f"no module {mod} in _CoqProject"
        return out
    page = f"{module}.html"
    if page not in page_anchors:
        page_anchors[page] = anchors(coqhtml / page)
    if name not in src.statements:
        out["reason"] = f"not stated in {src.vfile}"
    elif name not in page_anchors[page]:
        out["reason"] = f"coqdoc made no anchor {name} in {page}"
    else:
        out["href"] = f"coq/{page}#{name}"
    return out


def theorem_table(project: Project, sources: dict[str, Source], coqhtml: Path, spec: dict) -> list[dict]:
    """The groups of ``theorems.yaml`` with, for each theorem, its link or
    the reason why it has none, and the link of the library lemma that
    proves it (``proof``), if given."""
    checked = assumptions_checked(project)
    page_anchors: dict[str, set[str]] = {}
    groups = []
    for g in spec.get("groups", []):
        rows = []
        for t in g.get("theorems", []):
            full = t["name"]
            row = _link(project, sources, coqhtml, page_anchors, full)
            src = row.pop("src")
            row["closed"] = full in checked
            row["proof"] = None
            if t.get("proof"):
                proof = _link(project, sources, coqhtml, page_anchors, t["proof"])
                proof.pop("src")
                row["proof"] = proof
            note = t.get("note")
            row["blocks"] = blocks(note) if note else (src.doc_before(row["name"]) if src else [])
            rows.append(row)
        groups.append(
            {
                "id": g["id"],
                "title": g["title"],
                "summary": blocks(g.get("summary", "")),
                "theorems": rows,
            }
        )
    return groups


def render_example(model: Path, outdir: Path) -> dict | None:
    """The data-flow diagram of ``model`` (pyrosgen diagram) as SVG."""
    try:
        from pyrosgen.diagram import write_diagram
        from pyrosgen.frontend.validate import load_model

        m = load_model(model)
        name = f"{m.name}.svg"
        write_diagram(m, outdir / name, "svg")
    except Exception as exc:  # noqa: BLE001 - the page is still useful without it
        print(f"docs: warning: no diagram of {model}: {' '.join(str(exc).split())}", file=sys.stderr)
        return None
    return {"svg": name, "node": m.name, "model": model.name}


def build(coqdir: Path, out: Path, theorems: Path, example: Path | None) -> dict:
    project = read_project(coqdir)
    check_built(project)
    sources = {}
    for v in project.files:
        src = read_source(project, v)
        sources[src.module] = src
    try:
        spec = yaml.safe_load(theorems.read_text(encoding="utf-8")) or {}
    except (OSError, yaml.YAMLError) as exc:
        raise DocsError(f"cannot read {theorems}: {exc}") from exc

    out = out.resolve()
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(dir=out.parent, prefix=f".{out.name}."))
    try:
        coqhtml = tmp / "coq"
        coqhtml.mkdir()
        run_coqdoc(project, coqhtml)
        add_navigation(coqhtml)
        dangling = unlink_dangling(coqhtml)
        groups = theorem_table(project, sources, coqhtml, spec)
        modules = [
            {
                "module": s.module,
                "layer": project.layer(s.vfile),
                "vfile": s.vfile,
                "href": f"coq/{s.module}.html" if (coqhtml / f"{s.module}.html").is_file() else None,
                "title": s.title,
                "summary": s.summary,
            }
            for s in sources.values()
        ]
        # The modules by layer folder, in the order of _CoqProject.
        described = dict(project.layers)
        layers: list[dict] = []
        for m in modules:
            if not layers or layers[-1]["key"] != m["layer"]:
                folder = m["layer"]
                layers.append({
                    "key": folder,
                    "id": "layer-" + (folder.replace("/", "-") or "top"),
                    "folder": f"{project.phys}/{folder}" if folder else project.phys,
                    "description": described.get(folder, ""),
                    "modules": [],
                })
            layers[-1]["modules"].append(m)
        ex = render_example(example, tmp) if example else None
        rows = [t for g in groups for t in g["theorems"]]
        page = _env().get_template("index.html.j2").render(
            title=TITLE,
            logical=project.logical,
            phys=project.phys,
            modules=modules,
            layers=layers,
            groups=groups,
            example=ex,
            linked=sum(1 for t in rows if t["href"]),
            missing=sum(1 for t in rows if not t["href"]),
        )
        (tmp / "index.html").write_text(page, encoding="utf-8")
        os.chmod(tmp, 0o755)
        # Swap the new tree in.
        old = None
        if out.exists():
            old = Path(tempfile.mkdtemp(dir=out.parent, prefix=f".{out.name}.old."))
            os.replace(out, old / "docs")
        os.replace(tmp, out)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return {"modules": len(modules), "dangling": dangling, "linked": sum(1 for t in rows if t["href"]),
            "missing": [t["full"] for t in rows if not t["href"]]}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="Build the HTML documentation of the ROSGen Coq library.")
    ap.add_argument("--coq-dir", type=Path, default=HERE.parent, help="folder of _CoqProject (default: coq/)")
    ap.add_argument("--out", type=Path, default=HERE.parent.parent / "build" / "docs", help="output folder")
    ap.add_argument("--theorems", type=Path, default=HERE / "theorems.yaml", help="main theorems to list")
    ap.add_argument("--example", type=Path, help="a node model whose diagram the front page shows")
    args = ap.parse_args(argv)
    try:
        r = build(args.coq_dir, args.out, args.theorems, args.example)
    except DocsError as exc:
        print(f"docs: error: {exc}", file=sys.stderr)
        return 2
    print(
        f"docs: {r['modules']} modules, {r['linked']} main theorems linked, "
        f"{r['dangling']} dangling coqdoc links unlinked -> {args.out}/index.html"
    )
    if r["missing"]:
        print(f"docs: not yet in the library: {', '.join(r['missing'])}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
