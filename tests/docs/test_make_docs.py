"""``make docs``: coqdoc HTML of the whole library and the front page, every
link of which leads to an existing file and anchor."""

from __future__ import annotations

import re
import shutil
import subprocess

import pytest
import yaml

from support.docs import COQ, DOCS, REPO, Page, bad_links, project_modules, resolve_module, states, strip_comments


@pytest.fixture(scope="module")
def docs():
    assert shutil.which("coqdoc"), "coqdoc (Debian package coq) is needed"
    proc = subprocess.run(
        ["make", "--no-print-directory", "docs"], cwd=REPO, capture_output=True, text=True, timeout=3600
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert re.search(r"^docs: \d+ modules, \d+ main theorems linked", proc.stdout, re.M), proc.stdout
    return DOCS


def test_make_docs_builds_every_module(docs):
    modules = project_modules()
    assert len(modules) >= 12
    for module, _ in modules:
        page = docs / "coq" / f"{module}.html"
        assert page.is_file(), page
        assert f"Library {module}" in page.read_text(encoding="utf-8")
    assert (docs / "index.html").is_file()
    assert (docs / "coq" / "toc.html").is_file()
    assert (docs / "coq" / "index.html").is_file()  # coqdoc's index of identifiers
    toc = (docs / "coq" / "toc.html").read_text(encoding="utf-8")
    # The table of contents lists the modules in the order of _CoqProject.
    order = [toc.index(f'href="{m}.html"') for m, _ in modules]
    assert order == sorted(order)


def test_every_link_of_the_index_resolves(docs):
    index = docs / "index.html"
    checked, bad = bad_links([index])
    assert bad == []
    # toc, identifier index, one link per module, one per linked theorem, the diagram.
    assert checked >= 2 + len(project_modules()) + 4


def test_every_local_link_of_every_page_resolves(docs):
    pages = [docs / "index.html", *sorted((docs / "coq").glob("*.html"))]
    checked, bad = bad_links(pages)
    assert bad == []
    assert checked > 1000  # coqdoc links every identifier to its definition


def test_globalization_links(docs):
    page = Page(docs / "coq" / "ROSGen.glue.Generatorproof.html")
    # Identifiers of other modules link to their definitions (needs the .glob files).
    assert any(link.startswith("ROSGen.glue.Generator.html#generate") for link in page.links)
    assert any(link.startswith("ROSGen.glue.NodeModel.html#") for link in page.links)
    assert "generate_complete" in page.ids
    # Main.v's restatements link to the library lemmas they apply.
    main = Page(docs / "coq" / "ROSGen.Main.html")
    assert "ROSGen.glue.Loopproof.html#generate_node_ddc" in main.links
    assert "generate_node_ddc" in main.ids


def test_main_theorems_are_linked_iff_in_the_library(docs):
    spec = yaml.safe_load((COQ / "doc" / "theorems.yaml").read_text())
    modules = dict(project_modules())
    index = Page(docs / "index.html")
    text = (docs / "index.html").read_text(encoding="utf-8")
    rows = [t for g in spec["groups"] for t in g["theorems"]]
    assert len(rows) >= 20
    names = [t["name"] for t in rows] + [t["proof"] for t in rows if t.get("proof")]
    for full in names:
        mod, name = full.rsplit(".", 1)
        module = resolve_module(modules, mod)
        in_library = module is not None and states(modules[module], name)
        href = f"coq/{module}.html#{name}"
        assert (href in index.links) == in_library, full
        assert f"<code>{full}</code>" in text
        if in_library:
            assert index.link_text[href] == full
        else:
            after = text[text.index(f"<code>{full}</code>") :][:300]
            assert "not yet in the library" in after, full


def test_every_listed_theorem_is_a_closed_main_theorem(docs):
    """The front page lists restatements of Main.v (each checked closed by
    make -C coq check-assumptions) and the library lemmas that prove them."""
    spec = yaml.safe_load((COQ / "doc" / "theorems.yaml").read_text())
    main = strip_comments((COQ / "theories" / "Main.v").read_text(encoding="utf-8"))
    theorems = set(re.findall(r"^Theorem ([A-Za-z0-9_']+)", main, re.M))
    text = (docs / "index.html").read_text(encoding="utf-8")
    for g in spec["groups"]:
        for t in g["theorems"]:
            mod, name = t["name"].rsplit(".", 1)
            assert mod == "Main" and name in theorems, t["name"]
            assert t.get("proof"), t["name"]
            cell = text[text.index(f"<code>{t['name']}</code>") :][:400]
            assert '<span class="closed">closed</span>' in cell, t["name"]
            assert f"<code>{t['proof']}</code>" in cell, t["name"]
    # Each group T1-T5 lists a restatement of Main.v.
    ids = {g["id"] for g in spec["groups"]}
    assert {"T1", "T2", "T3", "T4", "T5"} <= ids


def test_existing_main_theorems_are_linked(docs):
    index = Page(docs / "index.html")
    for href in [
        "coq/ROSGen.Main.html#generate_node_ddc",                            # T2
        "coq/ROSGen.glue.Loopproof.html#generate_node_ddc",                  # T2, proof
        "coq/ROSGen.Main.html#generate_complete",                            # T4
        "coq/ROSGen.glue.Generatorproof.html#generate_sound",                # T4, proof
        "coq/ROSGen.Main.html#relation_consistency_input_glue",              # T3
        "coq/ROSGen.clight.Interpproof.html#interp_sound",                   # T5, proof
        "coq/ROSGen.Main.html#run_program_sound",                            # T5
    ]:
        assert href in index.links, href
    for group in ("T1", "T2", "T3", "T4", "T5", "T6", "T7"):
        assert group in index.ids


def test_layout_has_one_entry_per_module_in_order(docs):
    text = (docs / "index.html").read_text(encoding="utf-8")
    layout = text[text.index('id="layout"') :]
    found = re.findall(r'<dt id="([^"]+)">', layout)
    assert found == [m for m, _ in project_modules()]
    # Each entry carries the module's title from its header comment.
    assert "ROSGen.lib.Errors</a>: The error monad" in layout
    assert "ROSGen.clight.Interpproof</a>: Soundness of the interpreter" in layout
    assert "ROSGen.clight.Environment</a>: The ROS environment model" in layout
    # One heading per layer folder, in order, with the description that
    # _CoqProject gives it.
    layers = re.findall(r'<h3 id="layer-([a-z]+)"><code>([^<]+)</code>', layout)
    assert layers == [("lib", "theories/lib"), ("clight", "theories/clight"),
                      ("glue", "theories/glue"), ("ctrl", "theories/ctrl"), ("top", "theories"),
                      ("sys", "theories/sys")]
    assert "<code>theories/glue</code>: the node model, the generator" in layout


def test_coqdoc_pages_lead_back_to_the_index(docs):
    for module, _ in project_modules():
        page = Page(docs / "coq" / f"{module}.html")
        assert "../index.html" in page.links
        assert "toc.html" in page.links
