"""A model file name is user input that reaches generated text (comments of
the C, C++, CMake, XML and Coq files, the certificate): a name made to
break out of each (a newline, ``*)``, ``-->``, ``$(...)``, backticks,
``|``) is escaped everywhere, the node still builds, and configuring its
catkin package runs nothing."""

from __future__ import annotations

import shutil
import subprocess

from .conftest import LANDSHARK, LANDSHARK_CTL, pyrosgen

HOSTILE = "x\n$(touch PWNED1)`touch PWNED2`|*)-->\u202e.yaml"
NODE = "landshark_controller"


def test_hostile_model_file_name(tmp_path):
    d = tmp_path / "m"
    d.mkdir()
    model = d / HOSTILE
    shutil.copyfile(LANDSHARK, model)
    out = tmp_path / "out"
    run = pyrosgen("build", model, "--controller", LANDSHARK_CTL, "-o", out, "-q", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    manifest = out / f"{NODE}.manifest.json"
    import json

    assert json.loads(manifest.read_text())["source_name"] == HOSTILE  # JSON data, escaped by JSON
    texts = {p: p.read_bytes() for p in out.rglob("*") if p.is_file() and p != manifest
             and not p.name.endswith(".o") and "bin" not in p.parts}
    assert len(texts) > 10
    for p, data in texts.items():
        for piece in ("$(touch", "`touch", "*)-->", "\u202e"):
            assert piece.encode() not in data, (p, piece)
    # the comments name the file, escaped
    assert "x\\x0a\\x24\\x28touch" in (out / f"{NODE}_ros.cpp").read_text()
    assert "x\\x0a\\x24\\x28touch" in (out / NODE / "CMakeLists.txt").read_text()
    assert "`x\\x0a\\x24\\x28touch" in (out / f"{NODE}.certificate.md").read_text()
    # configuring the catkin package runs no command of the name
    r = subprocess.run(["cmake", "-S", str(out / NODE), "-B", str(tmp_path / "cmake"), "-DPYTHON_EXECUTABLE=/usr/bin/python3"],
                       capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=300, cwd=tmp_path)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    assert not list(tmp_path.rglob("PWNED*")) and not list(out.rglob("PWNED*"))
    # the package.xml is still well-formed XML
    import xml.dom.minidom

    xml.dom.minidom.parse(str(out / NODE / "package.xml"))
