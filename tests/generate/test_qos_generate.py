"""The QoS of rule 4.18 under ``pyrosgen generate`` for the target ROS 1:
accepted, ignored, and said so.  LandShark with a ``qos`` on every topic
generates, byte for byte, the files LandShark without it generates (the
QoS is not in the proved model), and the command prints one warning per
``qos``, at its place, on standard error (exit 0)."""

from __future__ import annotations

import subprocess
import sys

from support.generate import LANDSHARK, REPO


def _generate(model, out):
    return subprocess.run([sys.executable, "-m", "pyrosgen", "generate", "-q", str(model), "-o", str(out)],
                          capture_output=True, text=True, cwd=str(REPO), timeout=600)


def test_ros1_generate_ignores_the_qos_and_warns(tmp_path):
    text = LANDSHARK.read_text(encoding="utf-8")
    assert text.count("queue_size: 1}") == 4
    with_qos = text.replace("queue_size: 1}", "queue_size: 1, qos: sensor_data}", 3).replace(
        "queue_size: 1}", "queue_size: 1, qos: {durability: transient_local}}")
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    plain_model, qos_model = tmp_path / "a" / LANDSHARK.name, tmp_path / "b" / LANDSHARK.name
    plain_model.write_text(text, encoding="utf-8")
    qos_model.write_text(with_qos, encoding="utf-8")
    r1 = _generate(plain_model, tmp_path / "out_a")
    r2 = _generate(qos_model, tmp_path / "out_b")
    assert r1.returncode == 0 and r2.returncode == 0, r1.stderr + r2.stderr
    assert "warning" not in r1.stderr, r1.stderr
    warnings = [x for x in r2.stderr.splitlines() if ": warning: " in x]
    assert len(warnings) == 4, r2.stderr
    lines = with_qos.splitlines()
    for w, topic in zip(warnings, ("/landshark/left_wheel_velocity", "/landshark/right_wheel_velocity",
                                   "/landshark/gps_velocity", "/landshark_control/base_velocity")):
        n = next(i for i, x in enumerate(lines, 1) if f"name: {topic}," in x)
        col = lines[n - 1].index("qos: ") + len("qos: ") + 1
        assert w.startswith(f"{qos_model}:{n}:{col}: warning: topic '{topic}': qos ("), w
        assert w.endswith("the ROS 1 target ignores it: roscpp's TCPROS transport is reliable and volatile "
                          "[rule 4.18]"), w
    # the same node: every file generate writes but the manifest, digests and certificate
    # (which record the model file's digest) is the same, byte for byte
    a, b = tmp_path / "out_a", tmp_path / "out_b"
    names = sorted(p.name for p in a.iterdir())
    assert names == sorted(p.name for p in b.iterdir())
    recorded = {n for n in names if n.endswith((".manifest.json", ".sha256", ".certificate.md"))}
    assert len(recorded) == 3
    for n in sorted(set(names) - recorded):
        assert (a / n).read_bytes() == (b / n).read_bytes(), n
