"""Every reference in the project points into the project.

Code, tests, templates, generated files and documents cite the design
document ("DESIGN.md section N", "rule 4.N") and each other's files by path.
These tests fail on a citation of a section or rule that DESIGN.md does not
have, on a path that is not in the repository, and on any reference to a
file outside it.
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent

#: Files whose text is checked: everything tracked that is text.
TEXT_SUFFIXES = {
    ".py", ".v", ".j2", ".md", ".sh", ".yaml", ".yml", ".toml", ".c", ".h",
    ".cpp", ".ml", ".txt", ".cfg", ".html", "",
}

#: Top folders of the repository whose files may be cited by path.
CITABLE_TOPS = ("coq", "pyrosgen", "tests", "bench", "examples", "scripts", "docs",
                "theories", "templates", "extraction", "checks")

#: Folders below the top that documents and Coq files cite without their
#: parent (coq/README.md: theories/...); only checked in .md, .v and .j2.
BARE_TOPS = ("theories", "templates", "extraction", "checks")

#: A path of the repository as it is cited: a top folder, then path
#: characters, ending in a file name with an extension.
PATH_RE = re.compile(
    r"(?<![\w./-])((?:\.\./)*(?:%s)/[A-Za-z0-9_./-]*[A-Za-z0-9_-]\.(?:%s))\b"
    % ("|".join(CITABLE_TOPS), "|".join(("md", "py", "v", "j2", "sh", "yaml", "yml", "toml",
                                          "c", "h", "cpp", "ml", "msg", "json")))
)

#: Citations of the design document.
SECTION_RE = re.compile(r"DESIGN\.md,?\s+(?:section|§)\s*(\d+)(?:\.(\d+))?")
RULE_RE = re.compile(r"\brule\s+(4\.\d+)\b")

#: What may never appear: references to files outside the repository.
OUTSIDE_RE = re.compile(r"\.\./shared/|(?<![\w/])shared/(?:DESIGN|STYLE)\.md|(?<![\w/])seeds/\d")


def tracked_text_files() -> list[Path]:
    out = subprocess.run(
        ["git", "ls-files", "-z"], cwd=REPO, capture_output=True, check=True
    ).stdout.decode().split("\0")
    files = []
    for name in out:
        if not name:
            continue
        p = REPO / name
        if p.suffix not in TEXT_SUFFIXES or not p.is_file() or "results" in p.parts:
            continue
        if "golden" in p.parts or p.name == "test_references.py":
            continue  # golden: byte-exact generated output; this file: its own teeth
        files.append(p)
    return files


def design_sections() -> tuple[set[str], set[str]]:
    text = (REPO / "DESIGN.md").read_text()
    sections = set(re.findall(r"^##+ (\d+(?:\.\d+)?)\.? ", text, flags=re.M))
    rules = set(re.findall(r"^- \*\*(4\.\d+) ", text, flags=re.M))
    return sections, rules


def _texts():
    for p in tracked_text_files():
        try:
            yield p, p.read_text(encoding="utf-8")
        except UnicodeDecodeError:
            continue


def test_design_document_is_in_the_repository():
    sections, rules = design_sections()
    # The sections every citation relies on, and the numbered model rules.
    assert {str(n) for n in range(1, 10)} <= sections
    assert {f"4.{n}" for n in range(1, 11)} <= rules


def test_design_citations_resolve():
    sections, rules = design_sections()
    bad = []
    for p, text in _texts():
        for m in SECTION_RE.finditer(text):
            sec = m.group(1) if m.group(2) is None else f"{m.group(1)}.{m.group(2)}"
            if sec not in sections:
                bad.append(f"{p.relative_to(REPO)}: DESIGN.md section {sec} does not exist")
        for m in RULE_RE.finditer(text):
            if m.group(1) not in rules:
                bad.append(f"{p.relative_to(REPO)}: rule {m.group(1)} does not exist")
    assert not bad, "\n".join(bad)


def test_cited_paths_exist():
    bad = []
    for p, text in _texts():
        for m in PATH_RE.finditer(text):
            cited = m.group(1)
            if any(c in cited for c in "<>*{}$"):
                continue
            if cited.lstrip("./").split("/")[0] in BARE_TOPS and p.suffix not in (".md", ".v", ".j2"):
                continue  # code builds such paths in scratch folders too
            # A path is cited from the repository's root or from a folder
            # that holds the citing file (coq/README.md cites theories/...).
            bases = [REPO] + [d for d in p.parents if REPO in d.parents or d == REPO]
            if any((b / cited).exists() for b in bases):
                continue
            line = text.count("\n", 0, m.start()) + 1
            bad.append(f"{p.relative_to(REPO)}:{line}: {cited} is not in the repository")
    assert not bad, "\n".join(sorted(set(bad)))


def test_markdown_links_resolve():
    bad = []
    for p, text in _texts():
        if p.suffix != ".md":
            continue
        for m in re.finditer(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", text):
            target = m.group(1)
            if re.match(r"[a-z]+:", target):
                continue  # a URL
            if not (p.parent / target).exists():
                bad.append(f"{p.relative_to(REPO)}: link to {target} is broken")
    assert not bad, "\n".join(bad)


def test_nothing_cites_files_outside_the_repository():
    bad = [
        f"{p.relative_to(REPO)}:{text.count(chr(10), 0, m.start()) + 1}: {m.group(0)}"
        for p, text in _texts()
        for m in OUTSIDE_RE.finditer(text)
    ]
    assert not bad, "\n".join(bad)


@pytest.mark.parametrize(
    "text, kind",
    [
        ("see DESIGN.md section 12", "section"),
        ("(rule 4.77)", "rule"),
        ("in coq/theories/NoSuchFile.v", "path"),
        ("from ../" + "shared/DESIGN.md", "outside"),  # split: this file is scanned too
    ],
)
def test_the_checks_have_teeth(text, kind):
    """Each check above refuses a bad reference of its kind."""
    sections, rules = design_sections()
    if kind == "section":
        m = SECTION_RE.search(text)
        assert m and m.group(1) not in sections
    elif kind == "rule":
        m = RULE_RE.search(text)
        assert m and m.group(1) not in rules
    elif kind == "path":
        m = PATH_RE.search(text)
        assert m and not (REPO / m.group(1)).exists()
    else:
        assert OUTSIDE_RE.search(text)


def _layout_rows(marker: str) -> list[tuple[str, set[str]]]:
    """Rows ``| `folder/` | `a`, `b` | ... |`` of the README table that
    follows the line starting with ``marker``."""
    text = (REPO / "README.md").read_text()
    start = text.index(marker)
    rows = []
    for line in text[start:].splitlines()[1:]:
        if rows and not line.startswith("|"):
            break
        m = re.match(r"\| (`[^`]+`|\(top\)) \| ([^|]+) \|", line)
        if m and not line.startswith("|---"):
            rows.append((m.group(1).strip("`"), set(re.findall(r"`([A-Za-z_]+)`", m.group(2)))))
    return rows


@pytest.mark.parametrize("marker, root, suffix", [
    ("Python side (`pyrosgen/`", REPO / "pyrosgen", ".py"),
    ("The library (`coq/theories`", REPO / "coq" / "theories", ".v"),
])
def test_readme_layout_matches_the_tree(marker, root, suffix):
    """The README's layout tables list exactly the modules of each folder."""
    rows = _layout_rows(marker)
    assert rows, f"no layout table after {marker!r}"
    for folder, listed in rows:
        where = root if folder == "(top)" else root / folder
        actual = {p.stem for p in where.glob(f"*{suffix}") if p.stem not in ("__init__", "__main__")}
        assert listed == actual, f"README {folder}: listed {sorted(listed)}, tree has {sorted(actual)}"
    folders = {f.rstrip("/") for f, _ in rows if f != "(top)"}
    actual_folders = {p.name for p in root.iterdir() if p.is_dir() and not p.name.startswith(("_", "."))
                      and p.name != "templates"}
    assert folders == actual_folders
