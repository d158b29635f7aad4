"""Frama-C WP on the printed C (pyrosgen/verify/acsl.py, ``pyrosgen generate --wp``).

- the ACSL contracts generated from the model (callbacks, input_glue,
  output glues) are proved on LandShark and multi, every goal, and WP's
  memory-model hypotheses are all stated by the contracts;
- ``pyrosgen generate --wp`` prints the goal count;
- mutated glues (swapped sources, a missing zeroing, a copied neighbour
  leaf, a value changed by ``+ 0.0``) are not proved: the run fails;
- the nodes with timed topics (rule 4.12: the velocity guard, the
  ok_fresh_* models) are proved with the contracts of their clocks,
  fallbacks and derived inputs (``ros_now`` returns a global's value), and
  mutated timed glues (stale at the timeout, the age reversed, a flag not
  reset, the receipt time not kept, a float fallback one ulp off,
  ``is_new`` from ``received``, another saturation) are not.  (WP's
  simplifier reads float constants as real numbers, so ``-0.0`` and
  ``+0.0`` fallbacks are one to it: the sign of a zero fallback is checked
  bit for bit by the differential tests, ``fresh_constants``' ``-0.0``.)
- the stamped nodes (rule 4.13: the stamped LandShark and the laser guard,
  ``stamp: now``; the GPS-stamped LandShark, ``stamp: {from: ...}``) are
  proved with the contract of their stamps (``ros_time_sec`` and
  ``ros_time_nsec`` return globals' values; a copied stamp is the source
  topic's global's), and glues whose stamp takes its ``sec`` from
  ``ros_time_nsec``, stays zero, or is copied from another topic are not.
"""

from __future__ import annotations

import re
import shutil

import pytest

from pyrosgen import cli
from pyrosgen.generate import generate
from pyrosgen.verify.acsl import WPError, contracts, memory_hypotheses, run_wp
from pyrosgen.frontend.validate import load_model

from support.validation import EXAMPLES, LANDSHARK, REPO, TIMED_EXAMPLES, GeneratedNode


@pytest.mark.parametrize("key", list(EXAMPLES))
def test_wp_proves_the_examples(generated, key, tmp_path):
    node = generated[key]
    model = load_model(EXAMPLES[key][0])
    res = run_wp(model, node.glue, node.header, tmp_path / "wp")
    assert res.ok and res.proved == res.total
    cs = contracts(model)
    # one contract per callback, input_glue and each output glue
    assert [c.name for c in cs] == (
        [t.callback for t in model.subscribed] + ["input_glue"] + [t.output_glue for t in model.published])
    assert set(res.functions) == {c.name for c in cs}
    # every function contributes an ensures goal, an assigns goal per write, RTE goals per access
    for c in cs:
        assert f"typed_{c.name}_ensures : Valid" in res.output, c.name
    # a callback assigns exactly the leaves the node reads through its
    # global and the inputs of its direct relations (rule 4.16: multi's
    # /odom pose.covariance[35]), each ensured equal to the message's (the
    # others keep their values: assigns)
    u = model.controller.inputs.var_name
    assert sum(len(model.direct_relations(t)) for t in model.subscribed) == {"landshark": 0, "multi": 1}[key]
    for t in model.subscribed:
        c = next(c for c in cs if c.name == t.callback)
        read = model.read_leaves(t)
        direct = model.direct_relations(t)
        assert 0 < len(read) < len(model.leaf_paths(t.msg_type))
        assert c.assigns == (*(p.c_access(t.msg_var) for p in read), *(f"{u}.{r.input_target}" for r in direct))
        assert len(c.ensures) == len(read) + len(direct)
    for t in model.published:
        c = next(c for c in cs if c.name == t.output_glue)
        assert len(c.ensures) == len(model.leaf_paths(t.msg_type))
    # WP's hypotheses are exactly the separations the contracts state
    hyps = memory_hypotheses(res.output)
    assert {fn for fn, _ in hyps} == {c.name for c in cs if c.pointer}
    assert res.total >= {"landshark": 35, "multi": 100}[key]


@pytest.mark.parametrize("key", list(TIMED_EXAMPLES))
def test_wp_proves_the_timed_nodes(generated_timed, key, tmp_path):
    node = generated_timed[key]
    model = load_model(TIMED_EXAMPLES[key][0])
    res = run_wp(model, node.glue, node.header, tmp_path / "wp")
    assert res.ok and res.proved == res.total
    cs = {c.name: c for c in contracts(model)}
    for c in cs.values():
        assert f"typed_{c.name}_ensures : Valid" in res.output, c.name
    # the clock of each timed topic, in its callback
    for t in model.timed_topics:
        c = cs[t.callback]
        assert c.assigns == (*(p.c_access(t.msg_var) for p in model.read_leaves(t)),
                             t.time_var, t.new_var, t.rcvd_var)
        assert c.ensures[-3:] == (f"{t.time_var} == \\old(rosgen_wp_clock)", f"{t.new_var} == 1", f"{t.rcvd_var} == 1")
    # input_glue: one conjunct per relation, derived input and reset
    ig = cs["input_glue"]
    assert len(ig.ensures) == len(model.input_relations) + len(model.derived_relations) + len(model.timed_topics)
    fallbacks = [r for r in model.input_relations if r.fallback is not None]
    assert fallbacks or key == "fresh_flags"
    assert sum(" < (\\old(" in e for e in ig.ensures) == len(fallbacks)
    hyps = memory_hypotheses(res.output)
    assert {fn for fn, _ in hyps} == {c.name for c in cs.values() if c.pointer}


@pytest.mark.parametrize("key,old,new,failing", [
    ("velocity_guard", "(500000000ULL < _age)", "(500000000ULL <= _age)", "input_glue_ensures"),
    ("velocity_guard", "_age = (_now - teleop_cmd_vel_time);", "_age = (teleop_cmd_vel_time - _now);",
     "input_glue_ensures"),
    ("velocity_guard", "    nav_cmd_vel_new = 0;\n", "", "input_glue_ensures"),
    ("velocity_guard", "    teleop_cmd_vel_time = _t_ullong;\n", "", "teleop_cmd_vel_callback_ensures"),
    ("fresh_constants", "K_U.F32 = 0x1.99999ap-4f;", "K_U.F32 = 0x1.99999cp-4f;", "input_glue_ensures"),
    ("fresh_policies", "_t_uchar = cmd_new;", "_t_uchar = cmd_rcvd;", "input_glue_ensures"),
    ("fresh_policies", "F_U.Age = 4294967295U;", "F_U.Age = 4294967294U;", "input_glue_ensures"),
], ids=["stale-at-timeout", "age-reversed", "flag-not-reset", "receipt-not-kept", "float-one-ulp-off",
        "is-new-from-received", "other-saturation"])
def test_wp_fails_on_mutated_timed_glue(generated_timed, tmp_path, key, old, new, failing):
    node = generated_timed[key]
    work = tmp_path / "wp"
    work.mkdir()
    glue = node.glue.read_text()
    assert old in glue, old
    (work / node.glue.name).write_text(glue.replace(old, new, 1))
    shutil.copyfile(node.header, work / node.header.name)
    with pytest.raises(WPError) as info:
        run_wp(load_model(TIMED_EXAMPLES[key][0]), work / node.glue.name, work / node.header.name, work, timeout=3)
    msg = str(info.value)
    assert "goals proved, not all" in msg and failing in msg, msg


def test_generate_wp_prints_goal_count(capsys, tmp_path):
    code = cli.main(["generate", str(LANDSHARK), "-o", str(tmp_path / "out"), "--wp", "-q"])
    out = capsys.readouterr().out
    assert code == 0, out
    m = re.search(r"  WP        WP: (\d+)/(\d+) goals proved", out)
    assert m and m.group(1) == m.group(2) and int(m.group(1)) > 30, out


LS = "landshark_left_wheel_velocity_msg"
RS = "landshark_right_wheel_velocity_msg"


def _wp_refuses(model, node, tmp_path, old: str, new: str, failing: str, functions=None) -> None:
    """WP on ``node``'s glue with ``old`` replaced by ``new`` (once) fails,
    and names the goal ``failing`` among those not proved; only the
    contracts of ``functions`` are tried if given."""
    work = tmp_path / "wp"
    work.mkdir()
    glue = node.glue.read_text()
    assert glue.count(old) == 1, old
    (work / node.glue.name).write_text(glue.replace(old, new))
    shutil.copyfile(node.header, work / node.header.name)
    with pytest.raises(WPError) as info:
        run_wp(model, work / node.glue.name, work / node.header.name, work, timeout=3, functions=functions)
    msg = str(info.value)
    assert "goals proved, not all" in msg and failing in msg, msg


@pytest.mark.parametrize("name,old,new,failing", [
    ("swapped sources",
     f"    _t_double = {LS}.twist.linear.x;\n    Controller_U.In1 = _t_double;\n"
     f"    _t_double = {RS}.twist.linear.x;\n    Controller_U.In2 = _t_double;\n",
     f"    _t_double = {RS}.twist.linear.x;\n    Controller_U.In1 = _t_double;\n"
     f"    _t_double = {LS}.twist.linear.x;\n    Controller_U.In2 = _t_double;\n",
     "input_glue_ensures"),
    ("missing zeroing", "    (*command).twist.angular.y = 0x0p+0;\n", "", "output_glue_landshark_control_base_velocity_ensures"),
    ("neighbour leaf", f"    _t_double = (*msg).twist.linear.x;\n    {LS}.twist.linear.x",
     f"    _t_double = (*msg).twist.linear.y;\n    {LS}.twist.linear.x", "left_wheel_velocity_callback_ensures"),
    ("unread leaf written", f"    {LS}.twist.linear.x = _t_double;\n",
     f"    {LS}.twist.linear.x = _t_double;\n    {LS}.twist.linear.y = _t_double;\n",
     "left_wheel_velocity_callback_assigns"),
    ("plus zero", f"    _t_double = (*msg).twist.linear.x;\n    {LS}",
     f"    _t_double = (*msg).twist.linear.x + 0x0p+0;\n    {LS}", "left_wheel_velocity_callback_ensures"),
], ids=["swapped-sources", "missing-zeroing", "neighbour-leaf", "unread-leaf-written", "plus-zero"])
def test_wp_fails_on_mutated_glue(generated, tmp_path, name, old, new, failing):
    _wp_refuses(load_model(LANDSHARK), generated["landshark"], tmp_path, old, new, failing)


def test_generate_wp_failure_is_exit_2(monkeypatch, capsys, tmp_path):
    """A contract the glue does not meet (input_glue's In1 said to come from
    the right wheel): ``pyrosgen generate --wp`` exits 2, prints the goal
    count and the unproved goal, and writes nothing."""
    import dataclasses

    from pyrosgen.verify import acsl

    original = acsl.contracts

    def wrong(model):
        out = []
        for c in original(model):
            if c.name == "input_glue":
                ens = list(c.ensures)
                assert LS in ens[0]
                ens[0] = ens[0].replace(LS, RS)
                c = dataclasses.replace(c, ensures=tuple(ens))
            out.append(c)
        return out

    monkeypatch.setattr(acsl, "contracts", wrong)
    out = tmp_path / "out"
    code = cli.main(["generate", str(LANDSHARK), "-o", str(out), "--wp", "-q"])
    err = capsys.readouterr().err
    assert code == 2
    assert re.search(r"Frama-C WP: (\d+)/(\d+) goals proved, not all; nothing written", err), err
    assert "typed_input_glue_ensures" in err
    assert not out.exists()


def test_build_wp_writes_contracts_that_verify_rechecks(capsys, tmp_path):
    """``pyrosgen build --wp``: the contracts file is in the output folder
    and covered by the certificate; ``verify --wp`` re-runs Frama-C on it;
    with ``--model``, a weakened contracts file is refused even with its
    digests updated."""
    import hashlib
    import json

    out = tmp_path / "out"
    ctl = LANDSHARK.parent / "controller"
    code = cli.main(["build", str(LANDSHARK), "--controller", str(ctl), "-o", str(out), "--wp", "-q"])
    text = capsys.readouterr().out
    assert code == 0, text
    node = "landshark_controller"
    contracts_file = out / f"{node}_wp.c"
    manifest = json.loads((out / f"{node}.manifest.json").read_text())
    assert manifest["files"][contracts_file.name] == hashlib.sha256(contracts_file.read_bytes()).hexdigest()
    assert manifest["wp"]["proved"] == manifest["wp"]["total"] > 30
    assert re.search(r"  WP        WP: (\d+)/\1 goals proved", text), text
    cert = (out / f"{node}.certificate.md").read_text()
    assert f"{manifest['wp']['proved']}/{manifest['wp']['total']} goals" in cert and contracts_file.name in cert

    code = cli.main(["verify", str(out), "--wp", "--model", str(LANDSHARK), "-q"])
    text = capsys.readouterr().out
    assert code == 0, text
    assert "  ok      wp        WP: " in text and "contracts are those of landshark_controller.yaml" in text

    # weaken one ensures clause to \true, update the digests
    src = contracts_file.read_text()
    weak = re.sub(r"ensures [^;]*;", r"ensures \\true;", src, count=1)
    assert weak != src
    contracts_file.write_text(weak)
    manifest["files"][contracts_file.name] = hashlib.sha256(weak.encode()).hexdigest()
    (out / f"{node}.manifest.json").write_text(json.dumps(manifest))
    (out / f"{node}.sha256").write_text("".join(f"{v}  {n}\n" for n, v in sorted(manifest["files"].items())))
    code = cli.main(["verify", str(out), "--wp", "--model", str(LANDSHARK), "-q"])
    text = capsys.readouterr().out
    assert code == 1
    assert "  FAILED  wp" in text and "not the contracts of landshark_controller.yaml" in text, text


# --------------------------------------------------------------------------
# Stamps (rule 4.13): the output glue of a stamped topic writes the stamp

#: Stamped models: key -> (model file, node name, (old, new) edits of its
#: text).  The constant frame_id's capacity is cut from 128 bytes to 16
#: (``max_length``, rule 4.15): the output glue then stores 24 bytes
#: instead of 136 and WP proves it in seconds instead of minutes (the
#: stamp's statements and contract are the same).
STAMPED = {
    "landshark_stamped": (REPO / "examples" / "landshark" / "landshark_stamped.yaml", "landshark_stamped",
                          [("frame_id: base_link}", "frame_id: base_link, max_length: {header.frame_id: 16}}")]),
    "landshark_gps_stamped": (REPO / "examples" / "landshark" / "landshark_gps_stamped.yaml",
                              "landshark_gps_stamped", []),
    "laser_guard": (REPO / "examples" / "laser_guard" / "laser_guard.yaml", "laser_guard",
                    [("frame_id: base_link}", "frame_id: base_link, max_length: {header.frame_id: 16}}")]),
}


@pytest.fixture(scope="module")
def stamped(tmp_path_factory) -> dict[str, GeneratedNode]:
    """``pyrosgen generate`` on the stamped models of :data:`STAMPED`:
    key -> GeneratedNode (its model file, edited, is ``<out>/../<key>.yaml``)."""
    base = tmp_path_factory.mktemp("validation_generated_stamped")
    out = {}
    for key, (path, node, edits) in STAMPED.items():
        text = path.read_text()
        for old, new in edits:
            assert text.count(old) == 1, (key, old)
            text = text.replace(old, new)
        model = base / f"{key}.yaml"
        model.write_text(text)
        out[key] = GeneratedNode(key, node, base / key, generate(model, base / key))
    return out


def _stamped_model(stamped, key):
    return load_model(stamped[key].out.parent / f"{key}.yaml")


@pytest.mark.parametrize("key", list(STAMPED))
def test_wp_proves_the_stamped_nodes(stamped, key, tmp_path):
    node = stamped[key]
    model = _stamped_model(stamped, key)
    res = run_wp(model, node.glue, node.header, tmp_path / "wp")
    assert res.ok and res.proved == res.total
    cs = {c.name: c for c in contracts(model)}
    assert set(res.functions) == set(cs)
    for c in cs.values():
        assert f"typed_{c.name}_ensures : Valid" in res.output, c.name
    # the stamp's leaves: the cycle's time (ros_time_sec/nsec return two
    # globals the glue never writes), or the source topic's global's stamp
    (t,) = model.published
    c = cs[t.output_glue]
    assert len(c.ensures) == len(model.leaf_paths(t.msg_type))
    if t.stamp_from is None:
        src = ("rosgen_wp_sec", "rosgen_wp_nsec")
    else:
        s = next(s for s in model.subscribed if s.name == t.stamp_from)
        src = (f"{s.msg_var}.header.stamp.sec", f"{s.msg_var}.header.stamp.nsec")
        # its callback keeps the stamp in its global
        assert {"header.stamp.sec", "header.stamp.nsec"} <= {str(p) for p in model.read_leaves(s)}
    assert f"command->header.stamp.sec == \\old({src[0]})" in c.ensures
    assert f"command->header.stamp.nsec == \\old({src[1]})" in c.ensures
    wrapper = res.wrapper.read_text()
    now = t.stamp_from is None
    for g in ("rosgen_wp_sec", "rosgen_wp_nsec"):
        # declared, and stated separated from every pointer, only when the glue reads the time
        assert (f"extern unsigned int {g};" in wrapper) == now
        assert all((f"&{g}" in x.separated) == now for x in cs.values() if x.pointer)
    assert ("ensures \\result == rosgen_wp_sec;\n*/\nunsigned int ros_time_sec(void);" in wrapper) == now
    assert ("ensures \\result == rosgen_wp_nsec;\n*/\nunsigned int ros_time_nsec(void);" in wrapper) == now
    hyps = memory_hypotheses(res.output)
    assert {fn for fn, _ in hyps} == {c.name for c in cs.values() if c.pointer}


@pytest.mark.parametrize("key,old,new", [
    ("landshark_stamped", "_t_uint = ros_time_sec();", "_t_uint = ros_time_nsec();"),
    ("laser_guard", "    _t_uint = ros_time_sec();\n    (*command).header.stamp.sec = _t_uint;\n"
     "    _t_uint = ros_time_nsec();\n    (*command).header.stamp.nsec = _t_uint;\n", ""),
    ("landshark_gps_stamped", "_t_uint = landshark_gps_velocity_msg.header.stamp.sec;",
     "_t_uint = landshark_left_wheel_velocity_msg.header.stamp.sec;"),
], ids=["sec-from-nsec", "stamp-left-zero", "stamp-from-another-topic"])
def test_wp_fails_on_mutated_stamp(stamped, tmp_path, key, old, new):
    model = _stamped_model(stamped, key)
    og = model.published[0].output_glue
    # only the output glue: the mutant is there, and the other functions are proved above
    _wp_refuses(model, stamped[key], tmp_path, old, new, f"{og}_ensures", functions=(og,))
