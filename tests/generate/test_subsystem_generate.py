"""``pyrosgen generate`` on a diagram written with subsystems
(examples/landshark/landshark_subsystem.yaml): the front end expands the
Subsystem blocks, so Coq proves the expanded diagram with the same
theorems as the flat one (landshark_diagram.yaml), each closed; the
diagram Coq prints is the flat one's under the expanded names, and the
controller C is the flat one's under the same renaming."""

from __future__ import annotations

import json
import re
import subprocess

import pytest

from pyrosgen import cli
from pyrosgen.frontend.validate import load_model
from pyrosgen.generate import generate

from support.generate import REPO, require_library

SUBSYS = REPO / "examples" / "landshark" / "landshark_subsystem.yaml"
FLAT = REPO / "examples" / "landshark" / "landshark_diagram.yaml"
NODE = "landshark_controller"


@pytest.fixture(scope="module")
def folders(tmp_path_factory):
    require_library()
    base = tmp_path_factory.mktemp("subsystem")
    out = {}
    for name, model in (("sub", SUBSYS), ("flat", FLAT)):
        res = generate(model, base / name)
        assert res.record.controller is not None
        out[name] = base / name
    return out


def _renaming() -> dict[str, str]:
    flat = load_model(FLAT).controller.diagram
    sub = load_model(SUBSYS).controller.diagram
    names = {f.name: s.name for f, s in zip(flat.blocks, sub.blocks)}
    assert sorted(names) != sorted(names.values())      # some names do change
    return names


def _rename(text: str, names: dict[str, str]) -> str:
    """``text`` with every whole-word block name (and ``rtb_<name>``)
    renamed, all at once."""
    pattern = re.compile(r"\b(rtb_)?(" + "|".join(map(re.escape, sorted(names, key=len, reverse=True))) + r")\b")
    return pattern.sub(lambda m: (m.group(1) or "") + names[m.group(2)], text)


def test_theorems_are_closed(folders):
    d = folders["sub"]
    v = (d / f"{NODE}.v").read_text()
    for thm in (f"Theorem {NODE}_controller_wf : dg_wf the_diagram = true.",
                f"Theorem {NODE}_e2e : Endtoend.diagram_node_ok model the_program the_diagram.",
                f"Theorem {NODE}_linked : Link.linked_node_ok model the_program the_diagram."):
        assert thm in v
    manifest = json.loads((d / f"{NODE}.manifest.json").read_text())
    assert manifest["theorems"] == [f"{NODE}_ddc", f"{NODE}_ddc_target", f"{NODE}_wf", f"Ctrl.{NODE}_controller_wf",
                                    f"Ctrl.{NODE}_e2e", f"Ctrl.{NODE}_linked"]
    assert manifest["assumptions"].count("Closed under the global context") == 1
    assert manifest["assumptions"].count(" /\\ ") == 5  # the conjunction of the 6 theorems
    assert "Subsystem" not in v          # Coq sees ordinary blocks only


def test_printed_diagram_and_c_are_the_flat_ones_renamed(folders):
    names = _renaming()
    sub, flat = folders["sub"], folders["flat"]
    dsub = (sub / f"{NODE}_controller.diagram").read_text()
    assert "eq median_med float64 max median_lo_ab median_lo\n" in dsub
    assert dsub == _rename((flat / f"{NODE}_controller.diagram").read_text(), names)
    csub = (sub / f"{NODE}_controller.c").read_text()
    assert "rtb_median_med" in csub and "rtb_err_out" in csub
    assert csub == _rename((flat / f"{NODE}_controller.c").read_text(), names)


def test_controller_c_compiles(folders, tmp_path):
    c = folders["sub"] / f"{NODE}_controller.c"
    r = subprocess.run(["gcc", "-std=c11", "-pedantic", "-Wall", "-Wextra", "-Werror", "-c", str(c),
                        "-o", str(tmp_path / "c.o")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_verify(folders, capsys):
    code = cli.main(["verify", str(folders["sub"]), "--model", str(SUBSYS), "-q"])
    out = capsys.readouterr().out
    assert code == 0, out
    assert "the proved model is the model of landshark_subsystem.yaml" in out
    assert f"Ctrl.{NODE}_e2e, Ctrl.{NODE}_linked: Closed under the global context" in out
