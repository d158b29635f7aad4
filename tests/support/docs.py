"""Helpers of the documentation tests: an HTML link and anchor reader, and
a comment stripper for Coq sources (written independently of
coq/doc/mkdocs.py, which they check)."""

from __future__ import annotations

import html.parser
import importlib.util
import re
import sys
from pathlib import Path
from urllib.parse import unquote, urlsplit

REPO = Path(__file__).resolve().parent.parent.parent
COQ = REPO / "coq"
DOCS = REPO / "build" / "docs"
MKDOCS = COQ / "doc" / "mkdocs.py"


class Page(html.parser.HTMLParser):
    """Anchors (``id``/``name``), links (``href``/``src``) and the text of
    each link of one HTML page."""

    def __init__(self, path: Path):
        super().__init__(convert_charrefs=True)
        self.path = path
        self.ids: set[str] = set()
        self.links: list[str] = []
        self.link_text: dict[str, str] = {}
        self._open: str | None = None
        self._buf = ""
        self.feed(path.read_text(encoding="utf-8"))
        self.close()

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        for k in ("id", "name"):
            if a.get(k):
                self.ids.add(a[k])
        for k in ("href", "src"):
            if a.get(k) is not None:
                self.links.append(a[k])
        if tag == "a" and a.get("href") is not None:
            self._open, self._buf = a["href"], ""

    def handle_data(self, data):
        if self._open is not None:
            self._buf += data

    def handle_endtag(self, tag):
        if tag == "a" and self._open is not None:
            self.link_text.setdefault(self._open, self._buf)
            self._open = None


def bad_links(pages: list[Path]) -> tuple[int, list[str]]:
    """Check every local link of ``pages``: the file exists and, for a
    ``#fragment`` into an HTML file, the anchor exists.  Returns the
    number of local links checked and the bad ones."""
    cache: dict[Path, Page] = {}

    def page(p: Path) -> Page:
        p = p.resolve()
        if p not in cache:
            cache[p] = Page(p)
        return cache[p]

    checked, bad = 0, []
    for p in pages:
        for link in page(p).links:
            u = urlsplit(link)
            if u.scheme or u.netloc:
                continue
            checked += 1
            target = p if not u.path else (p.parent / unquote(u.path))
            if not target.exists():
                bad.append(f"{p.name}: {link}: no file")
            elif u.fragment and target.suffix == ".html" and unquote(u.fragment) not in page(target).ids:
                bad.append(f"{p.name}: {link}: no anchor")
    return checked, bad


def strip_comments(text: str) -> str:
    """Coq text without its (nested) comments."""
    inner = re.compile(r"\(\*(?:(?!\(\*|\*\)).)*?\*\)", re.S)
    while True:
        new = inner.sub(" ", text)
        if new == text:
            return text
        text = new


def states(vfile: Path, name: str) -> bool:
    """Whether ``vfile`` states ``name`` (outside comments)."""
    code = strip_comments(vfile.read_text(encoding="utf-8"))
    kinds = "Theorem|Lemma|Corollary|Proposition|Fact|Remark"
    return re.search(rf"^\s*(?:{kinds})\s+{re.escape(name)}\b", code, re.M) is not None


def project_modules(coq: Path = COQ) -> list[tuple[str, Path]]:
    """(``ROSGen.layer.M``, path) for every module of ``_CoqProject``, in order."""
    out = []
    for line in (coq / "_CoqProject").read_text().splitlines():
        line = line.strip()
        if line.startswith("theories/") and line.endswith(".v"):
            out.append(("ROSGen." + line[len("theories/") : -2].replace("/", "."), coq / line))
    return out


def load_mkdocs():
    spec = importlib.util.spec_from_file_location("rosgen_mkdocs", MKDOCS)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod  # dataclasses look their module up there
    spec.loader.exec_module(mod)
    return mod


def resolve_module(modules: dict[str, Path], name: str, logical: str = "ROSGen") -> str | None:
    """The module that ``name`` designates in theorems.yaml: a path under the
    library (``glue.Glueproof``) or a base name found once (``Glueproof``)."""
    if f"{logical}.{name}" in modules:
        return f"{logical}.{name}"
    found = [m for m in modules if m.endswith("." + name)]
    return found[0] if len(found) == 1 else None
