"""The C++ headers of the standard message packages: every package the
front end knows has its Debian package, which ``scripts/deps.sh``
installs; a model whose headers are missing is refused by build before
the proof (exit 2, naming the Debian package and the topic's line), and
check says so in a note (exit 0: the model is valid)."""

from __future__ import annotations

import re
from pathlib import Path

from rosbags.typesys import Stores, get_typestore

from pyrosgen import cli
from pyrosgen.frontend import msgdeb
from pyrosgen.frontend.msgload import MsgRegistry

ROOT = Path(__file__).resolve().parents[2]
LANDSHARK = ROOT / "examples" / "landshark" / "landshark_controller.yaml"


def test_every_known_package_has_its_debian_package():
    """The packages of the message types the front end accepts are those of
    DEBIAN_DEV, and deps.sh installs each one's Debian package."""
    reg = MsgRegistry()
    known = set()
    for name in get_typestore(Stores.ROS1_NOETIC).fielddefs:
        pkg, _, short = name.split("/")
        if reg.check_type_name(f"{pkg}/{short}") is None:
            known.add(pkg)
    assert known == set(msgdeb.DEBIAN_DEV), sorted(known ^ set(msgdeb.DEBIAN_DEV))
    deps = (ROOT / "scripts" / "deps.sh").read_text()
    listed = set(re.search(r"PKGS=\((.*?)\n\)", deps, re.S).group(1).split())
    assert set(msgdeb.DEBIAN_DEV.values()) <= listed, sorted(set(msgdeb.DEBIAN_DEV.values()) - listed)


def test_missing_headers_refused_by_build_noted_by_check(monkeypatch, tmp_path, capsys):
    roots = tmp_path / "include"
    (roots / "std_msgs").mkdir(parents=True)
    (roots / "std_msgs" / "Header.h").write_text("")
    monkeypatch.setattr(msgdeb, "_ROOTS", (str(roots),))
    monkeypatch.delenv("CPATH", raising=False)
    monkeypatch.delenv("CPLUS_INCLUDE_PATH", raising=False)
    out = tmp_path / "out"
    code = cli.main(["build", str(LANDSHARK), "--controller", str(LANDSHARK.parent / "controller"), "-o", str(out)])
    _, err = capsys.readouterr()
    assert code == 2, err
    assert "the C++ headers of 3 message types of the model are not installed" in err
    line = next(i for i, ln in enumerate(LANDSHARK.read_text().splitlines(), 1) if "direction: subscribe" in ln)
    assert (f"{LANDSHARK}:{line}:5: error: geometry_msgs/TwistStamped (topic /landshark/left_wheel_velocity): "
            "its C++ header geometry_msgs/TwistStamped.h is not installed: install the Debian package "
            "libgeometry-msgs-dev (make deps installs it)") in err
    assert "geometry_msgs/Twist.h" in err and "geometry_msgs/Vector3.h" in err and "std_msgs/Header.h" not in err
    assert not out.exists() and not list(tmp_path.glob(".pyrosgen-build-*"))
    # check: the model is valid, a note says what building needs
    code = cli.main(["check", str(LANDSHARK)])
    o, err = capsys.readouterr()
    assert code == 0 and ": ok: node landshark_controller" in o
    assert f"{LANDSHARK}:{line}:5: note: geometry_msgs/TwistStamped (topic /landshark/left_wheel_velocity)" in err
    assert "(pyrosgen build needs it)" in err
    # with the headers there: no note
    (roots / "geometry_msgs").mkdir()
    for t in ("TwistStamped", "Twist", "Vector3"):
        (roots / "geometry_msgs" / f"{t}.h").write_text("")
    assert cli.main(["check", str(LANDSHARK)]) == 0
    assert "note" not in capsys.readouterr().err
