"""coq/doc/mkdocs.py on a small library made for the test: which theorems
it links, what it says of the others, how it reads coqdoc comments, and
that a stale build is refused with the old documentation kept."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

from support.docs import Page, bad_links, load_mkdocs

A_V = """\
(** * Module A: a title *)

(** The first paragraph of [A], with [nested [brackets]] and a list:
    - an item with [x];
    - another item,
      continued.

    A second paragraph, not part of the summary. *)

(** The documentation of [real]. *)
Theorem real : True.
Proof. exact I. Qed.

(* Theorem ghost : True.  (only in a comment) *)
From Coq Require Import String.
Definition s := "(* Theorem ghost2 : True. *)"%string.

Section S.
Lemma in_section : 1 = 1.
Proof. reflexivity. Qed.
End S.
"""

B_V = """\
(** * Module B *)

(** Uses [A.real]. *)
From Fake Require Import A.

Lemma b_uses : True.
Proof. exact real. Qed.
"""

THEOREMS = """\
groups:
  - id: G1
    title: Group one
    summary: "About [real]."
    theorems:
      - name: A.real
      - name: A.ghost
      - name: A.ghost2
        note: "A theorem that is only in a string."
      - name: A.in_section
      - name: C.nothing
      - name: B.b_uses
"""


@pytest.fixture(scope="module")
def mkdocs():
    return load_mkdocs()


@pytest.fixture(scope="module")
def fake(tmp_path_factory):
    if not shutil.which("coqc"):
        pytest.fail("coqc is needed")
    root = tmp_path_factory.mktemp("fake") / "coq"
    (root / "theories").mkdir(parents=True)
    (root / "_CoqProject").write_text("# a test library\n-R theories Fake\ntheories/A.v\ntheories/B.v\n")
    (root / "theories" / "A.v").write_text(A_V)
    (root / "theories" / "B.v").write_text(B_V)
    (root / "theorems.yaml").write_text(THEOREMS)
    for v in ("theories/A.v", "theories/B.v"):
        subprocess.run(["coqc", "-R", "theories", "Fake", v], cwd=root, check=True, capture_output=True)
    return root


def build(mkdocs, fake, out):
    return mkdocs.main(["--coq-dir", str(fake), "--out", str(out), "--theorems", str(fake / "theorems.yaml")])


def test_links_only_stated_theorems(mkdocs, fake, tmp_path, capsys):
    out = tmp_path / "docs"
    assert build(mkdocs, fake, out) == 0
    stdout = capsys.readouterr().out
    assert "docs: 2 modules, 3 main theorems linked" in stdout
    assert "not yet in the library: A.ghost, A.ghost2, C.nothing" in stdout
    index = Page(out / "index.html")
    theorem_links = sorted(link for link in index.links if "#" in link)
    assert theorem_links == [
        "coq/Fake.A.html#in_section",
        "coq/Fake.A.html#real",
        "coq/Fake.B.html#b_uses",
    ]
    text = (out / "index.html").read_text()
    assert 'title="not stated in theories/A.v">not yet in the library' in text
    assert 'title="no module C in _CoqProject">not yet in the library' in text
    # Descriptions: the comment above the statement, or the note.
    assert "<p>The documentation of <code>real</code>.</p>" in text
    assert "<p>A theorem that is only in a string.</p>" in text
    checked, bad = bad_links([out / "index.html", *sorted((out / "coq").glob("*.html"))])
    assert bad == [] and checked > 10


def test_module_summary(mkdocs, fake, tmp_path):
    out = tmp_path / "docs"
    assert build(mkdocs, fake, out) == 0
    text = (out / "index.html").read_text()
    assert '<dt id="Fake.A"><a href="coq/Fake.A.html">Fake.A</a>: Module A: a title' in text
    assert (
        "<p>The first paragraph of <code>A</code>, with <code>nested [brackets]</code> and a list:</p>"
        in text
    )
    assert "<li>an item with <code>x</code>;</li>" in text
    assert "<li>another item, continued.</li>" in text
    assert "second paragraph" not in text
    assert '<dt id="Fake.B"><a href="coq/Fake.B.html">Fake.B</a>: Module B' in text


def test_stale_build_is_refused_and_old_docs_kept(mkdocs, fake, tmp_path, capsys):
    out = tmp_path / "docs"
    assert build(mkdocs, fake, out) == 0
    before = (out / "index.html").read_bytes()
    a = fake / "theories" / "A.v"
    st = a.stat()
    try:
        later = (fake / "theories" / "A.vo").stat().st_mtime + 10
        os.utime(a, (later, later))
        assert build(mkdocs, fake, out) == 2
        err = capsys.readouterr().err
        assert "docs: error: no up-to-date .glob file for theories/A.v" in err
        assert (out / "index.html").read_bytes() == before
        assert sorted(p.name for p in tmp_path.iterdir()) == ["docs"]  # no temporary left
    finally:
        os.utime(a, ns=(st.st_atime_ns, st.st_mtime_ns))


def test_segments_and_blocks(mkdocs):
    seg = mkdocs.segments
    assert seg("a [b] c") == [
        {"code": False, "text": "a "}, {"code": True, "text": "b"}, {"code": False, "text": " c"},
    ]
    assert seg("x [a [b] c] y")[1] == {"code": True, "text": "a [b] c"}
    assert seg("open [never") == [{"code": False, "text": "open [never"}]
    blocks = mkdocs.blocks("One\n  two.\n\n- i1\n- i2\n  more\n\n<<\nverbatim\n>>\nafter")
    assert blocks == [
        {"kind": "p", "segs": [{"code": False, "text": "One two."}]},
        {"kind": "ul", "items": [[{"code": False, "text": "i1"}], [{"code": False, "text": "i2 more"}]]},
    ]


def test_scan_blanks_comments_not_strings(mkdocs):
    code, docs = mkdocs.scan('a (* x (* y *) z *) "(* s *)" (** d [e] *) b')
    assert "x" not in code and "z" not in code
    assert '"(* s *)"' in code
    assert [d.body for d in docs] == [" d [e] "]
    assert len(code) == len('a (* x (* y *) z *) "(* s *)" (** d [e] *) b')


NESTED_THEOREMS = """\
groups:
  - id: G1
    title: Group one
    theorems:
      - name: A.real
        proof: lib.A.in_section
      - name: B.b_uses
        proof: A.nothing
"""


@pytest.fixture(scope="module")
def nested(tmp_path_factory):
    """A library in layer folders, as coq/theories is (lib/A.v, B.v)."""
    root = tmp_path_factory.mktemp("nested") / "coq"
    (root / "theories" / "lib").mkdir(parents=True)
    (root / "_CoqProject").write_text(
        "# A test library in folders\n-R theories Fake\n"
        "# lib: the first layer\ntheories/lib/A.v\n# top: the rest\ntheories/B.v\n"
    )
    (root / "theories" / "lib" / "A.v").write_text(A_V)
    (root / "theories" / "B.v").write_text(B_V)
    (root / "theorems.yaml").write_text(NESTED_THEOREMS)
    for v in ("theories/lib/A.v", "theories/B.v"):
        subprocess.run(["coqc", "-R", "theories", "Fake", v], cwd=root, check=True, capture_output=True)
    return root


def test_layer_folders(mkdocs, nested, tmp_path, capsys):
    out = tmp_path / "docs"
    assert mkdocs.main(["--coq-dir", str(nested), "--out", str(out),
                        "--theorems", str(nested / "theorems.yaml")]) == 0
    stdout = capsys.readouterr().out
    assert "docs: 2 modules, 2 main theorems linked" in stdout
    index = Page(out / "index.html")
    # Base names and paths under the library both find the module.
    assert "coq/Fake.lib.A.html#real" in index.links
    assert "coq/Fake.B.html#b_uses" in index.links
    assert "coq/Fake.lib.A.html#in_section" in index.links  # the proof of A.real
    text = (out / "index.html").read_text()
    assert 'title="not stated in theories/lib/A.v">(not yet in the library)' in text  # A.nothing
    assert '<h3 id="layer-lib"><code>theories/lib</code>: the first layer</h3>' in text
    assert '<h3 id="layer-top"><code>theories</code>: the rest</h3>' in text
    assert (out / "coq" / "Fake.lib.A.html").is_file()
    checked, bad = bad_links([out / "index.html", *sorted((out / "coq").glob("*.html"))])
    assert bad == [] and checked > 10


def test_module_resolution(mkdocs, nested):
    project = mkdocs.read_project(nested)
    assert project.resolve("A") == "Fake.lib.A"
    assert project.resolve("lib.A") == "Fake.lib.A"
    assert project.resolve("B") == "Fake.B"
    assert project.resolve("C") is None
    assert project.layer("theories/lib/A.v") == "lib" and project.layer("theories/B.v") == ""
    assert dict(project.layers) == {"lib": "the first layer", "": "the rest"}
