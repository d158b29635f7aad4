"""A stamped node through the whole pipeline (rule 4.13): ``generate`` on
examples/landshark/landshark_stamped.yaml proves its theorem, prints the
stamp code after the output relation's copy, shows it in the certificate
with its C lines, and ``verify`` accepts the folder; the seam catches a
per-node file that drops the stamp (it still proves a theorem, about an
unstamped node) or stamps another topic.  The same for
examples/landshark/landshark_gps_stamped.yaml, whose stamp is copied
from the newest GPS message (``stamp: {from: ...}``)."""

from __future__ import annotations

import re

import pytest

import pyrosgen.generate as gen
from pyrosgen import cli

from support.generate import REPO as ROOT, generate_with_tampered_node_file, require_library

STAMPED = ROOT / "examples" / "landshark" / "landshark_stamped.yaml"
STAMPS = '[("landshark_control_base_velocity", [PField "header"; PField "stamp"])]'


def _generated(tmp_path_factory, model, name):
    """``model`` generated once into a fresh folder."""
    require_library()
    out = tmp_path_factory.mktemp(name) / "out"
    assert cli.main(["generate", str(model), "-o", str(out), "-q"]) == 0
    return out


def _output_glue(c: str) -> tuple[str, list[str]]:
    """The body of the base_velocity output glue, and its lines stripped."""
    body = c[c.index("void output_glue_landshark_control_base_velocity(struct geometry_msgs_TwistStamped *command)\n{"):]
    body = body[:body.index("\n}\n")]
    return body, [ln.strip() for ln in body.splitlines()]


@pytest.fixture(scope="module")
def stamped(tmp_path_factory):
    return _generated(tmp_path_factory, STAMPED, "stamped")


def test_glue_stamps_after_the_copies(stamped):
    c = (stamped / "landshark_stamped_glue.c").read_text()
    body, lines = _output_glue(c)
    copy = lines.index("(*command).twist.linear.x = _t_double;")
    assert lines[copy + 1:copy + 5] == [
        "_t_uint = ros_time_sec();", "(*command).header.stamp.sec = _t_uint;",
        "_t_uint = ros_time_nsec();", "(*command).header.stamp.nsec = _t_uint;"]
    # the zeroing comes first
    assert lines.index("(*command).header.stamp.sec = 0U;") < copy
    assert re.search(r"^unsigned int ros_time_sec\(void\);$", c, re.M)


def test_certificate_shows_the_stamp(stamped):
    cert = (stamped / "landshark_stamped.certificate.md").read_text()
    section = cert[cert.index("## Stamps"):cert.index("## Trusted, not proved")]
    assert "`/landshark_control/base_velocity header.stamp` (time)" in section
    assert "_t_uint = ros_time_nsec();" in section
    assert "landshark_stamped.model" in cert or "stamp landshark_control_base_velocity header.stamp" in \
        (stamped / "landshark_stamped.model").read_text()


def test_verify_accepts_the_folder(stamped, capsys):
    assert cli.main(["verify", str(stamped)]) == 0, capsys.readouterr().err


@pytest.mark.parametrize("name, new", [
    ("stamp dropped", "[]"),
    ("another topic stamped", STAMPS.replace("landshark_control_base_velocity", "landshark_gps_velocity")),
])
def test_tampered_stamp_is_refused(name, new, monkeypatch, capsys, tmp_path):
    require_library()
    out = tmp_path / "out"
    code, err = generate_with_tampered_node_file(STAMPED, STAMPS, new, monkeypatch, capsys, out)
    assert not out.exists()
    if name == "stamp dropped":
        assert code == 2, err
        # the node still proves its theorem, about an unstamped node: the seam refuses it
        assert "is not the model of the YAML file" in err and "stamp" in err
    else:
        # Coq refuses a stamp on a subscribed topic (Wellformed.stamp_ok)
        assert code == 1, err
        assert "bad stamp (rule 4.13)" in err


# --------------------------------------------------------------------------
# A stamp copied from a subscribed topic

COPIED = ROOT / "examples" / "landshark" / "landshark_gps_stamped.yaml"
SOURCE = '[("landshark_control_base_velocity", ("landshark_gps_velocity", [PField "header"; PField "stamp"]))]'


@pytest.fixture(scope="module")
def copied(tmp_path_factory):
    return _generated(tmp_path_factory, COPIED, "copied")


def test_glue_copies_the_gps_stamp(copied):
    c = (copied / "landshark_gps_stamped_glue.c").read_text()
    body, lines = _output_glue(c)
    copy = lines.index("(*command).twist.linear.x = _t_double;")
    assert lines[copy + 1:copy + 5] == [
        "_t_uint = landshark_gps_velocity_msg.header.stamp.sec;", "(*command).header.stamp.sec = _t_uint;",
        "_t_uint = landshark_gps_velocity_msg.header.stamp.nsec;", "(*command).header.stamp.nsec = _t_uint;"]
    assert "ros_time_sec()" not in body


def test_certificate_names_the_source(copied):
    cert = (copied / "landshark_gps_stamped.certificate.md").read_text()
    section = cert[cert.index("## Stamps"):cert.index("## Trusted, not proved")]
    assert "(time, copied from `/landshark/gps_velocity header.stamp`)" in section
    assert "_t_uint = landshark_gps_velocity_msg.header.stamp.nsec;" in section
    assert "stamp_from landshark_control_base_velocity landshark_gps_velocity header.stamp" in \
        (copied / "landshark_gps_stamped.model").read_text()


def test_verify_accepts_the_copied_folder(copied, capsys):
    assert cli.main(["verify", str(copied)]) == 0, capsys.readouterr().err


@pytest.mark.parametrize("name, new", [
    ("source dropped", "[]"),
    ("another source", SOURCE.replace("landshark_gps_velocity", "landshark_left_wheel_velocity")),
])
def test_tampered_source_is_refused(name, new, monkeypatch, capsys, tmp_path):
    """A per-node file whose stamp comes from the time, or from the left
    wheel, still proves a theorem, about another node: the seam refuses it."""
    require_library()
    original = gen.render_node_file

    def tampered(model, **kw):
        text = original(model, **kw)
        assert SOURCE in text
        return text.replace(SOURCE, new, 1)

    monkeypatch.setattr(gen, "render_node_file", tampered)
    out = tmp_path / "out"
    code = cli.main(["generate", str(COPIED), "-o", str(out), "-q"])
    err = capsys.readouterr().err
    assert not out.exists()
    assert code == 2, err
    assert "is not the model of the YAML file" in err and "stamp_from" in err
