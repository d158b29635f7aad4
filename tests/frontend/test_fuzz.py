"""Property-based tests: whatever the input, ``load_model`` returns a
NodeModel or raises InvalidNodeModel, and ``pyrosgen check`` exits 0 or 1
without a traceback.  A model that loads satisfies every rule of DESIGN.md 4.
"""

from __future__ import annotations

import atexit
import contextlib
import copy
import io
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pyrosgen import InvalidNodeModel, NodeModel, load_model
from pyrosgen.cli import main
from pyrosgen.frontend.msgmodel import PRIMITIVES
from pyrosgen.frontend.names import identifier_problem, topic_name_problem

from support.frontend import LANDSHARK, MULTI

LS_TEXT = LANDSHARK.read_text(encoding="utf-8")
LS_DATA = yaml.safe_load(LS_TEXT)
MULTI_DATA = yaml.safe_load(MULTI.read_text(encoding="utf-8"))
MULTI_DATA["msg_paths"] = [str((MULTI.parent / p).resolve()) for p in MULTI_DATA["msg_paths"]]

# PYROSGEN_FUZZ_EXAMPLES raises the budget for a longer local run.
FUZZ = settings(
    max_examples=int(os.environ.get("PYROSGEN_FUZZ_EXAMPLES", "200")),
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)

DIAG = re.compile(r"^.+?(:\d+:\d+)?: error: [ -~]+$")

_WORKDIR = Path(tempfile.mkdtemp(prefix="pyrosgen-fuzz-"))
atexit.register(shutil.rmtree, _WORKDIR, ignore_errors=True)


def _write(data: bytes) -> Path:
    p = _WORKDIR / "model.yaml"
    p.write_bytes(data)
    return p


def check_invariants(m: NodeModel) -> None:
    """What every successfully loaded model guarantees to the emitters."""
    ctrl = m.controller
    inputs = {f.name: f.prim for f in ctrl.inputs.fields}
    outputs = {f.name: f.prim for f in ctrl.outputs.fields}
    assert inputs and outputs
    assert 1 <= m.period_ms and m.topics
    assert sorted(r.input_field for r in m.input_relations) == sorted(inputs)
    msgs = {t.name: t for t in m.messages}
    for r in m.input_relations:
        assert r.topic.is_subscribed and r.topic in m.topics
        assert r.path.prim == inputs[r.input_field] and r.path.prim in PRIMITIVES
        assert r.path in m.leaf_paths(r.topic.msg_type)
    seen = set()
    for r in m.output_relations:
        assert r.topic.is_published and r.topic in m.topics
        assert r.path.prim == outputs[r.output_field]
        assert r.path in m.leaf_paths(r.topic.msg_type)
        assert (r.topic.name, r.path) not in seen
        seen.add((r.topic.name, r.path))
    names = [m.name, ctrl.name, ctrl.inputs.var_name, ctrl.outputs.var_name]
    names += list(inputs) + list(outputs)
    for n in names:
        assert identifier_problem(n) is None, n
    globals_ = [ctrl.inputs.var_name, ctrl.outputs.var_name, ctrl.step_fn, ctrl.initialize_fn,
                ctrl.inputs.struct_name, ctrl.outputs.struct_name, "input_glue", "loop", "main"]
    for t in m.topics:
        assert topic_name_problem(t.name) is None
        assert 1 <= t.queue_size
        assert t.msg_type in msgs
        globals_ += list(t.derived_names())
    globals_ += [t.c_name for t in m.messages]
    assert len(globals_) == len(set(globals_))
    for n in globals_:
        assert identifier_problem(n, global_scope=True) is None, n
    order = [t.name for t in m.messages]
    for t in m.messages:
        assert t.fields
        for f in t.fields:
            if f.kind == "msg":
                assert order.index(f.msg) < order.index(t.name)


def load_or_invalid(path: Path) -> NodeModel | None:
    try:
        m = load_model(path)
    except InvalidNodeModel as exc:
        assert exc.diagnostics
        for d in exc.diagnostics:
            assert DIAG.match(str(d)), str(d)
        return None
    check_invariants(m)
    return m


def cli_exits_0_or_1(path: Path) -> int:
    out_buf, err_buf = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out_buf), contextlib.redirect_stderr(err_buf):
        code = main(["check", str(path)])
    out, err = out_buf.getvalue(), err_buf.getvalue()
    assert code in (0, 1), err
    assert "Traceback" not in err and "internal error" not in err
    if code == 1:
        assert out == ""
        assert err and all(DIAG.match(line) for line in err.splitlines()), err
    else:
        assert err == "" and ": ok: node " in out
    return code


# --------------------------------------------------------------------------
# Strategy 1: arbitrary bytes


@FUZZ
@given(st.binary(max_size=4000))
def test_arbitrary_bytes(data):
    load_or_invalid(_write(data))


@FUZZ
@given(st.text(alphabet=st.sampled_from(list("{}[]:,-#&*!|>'\"%@`?\n\t abc01/._~\\")), max_size=400))
def test_yaml_punctuation_soup(text):
    load_or_invalid(_write(text.encode("utf-8")))


# --------------------------------------------------------------------------
# Strategy 2: arbitrary YAML trees

KEYS = [
    "node", "controller", "topics", "relations", "msg_paths", "name", "period_ms",
    "inputs", "outputs", "fields", "direction", "type", "queue_size", "topic",
    "field", "input", "output", "In1", "Out1",
]
SCALARS = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-(2**70), max_value=2**70),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=20),
    st.sampled_from(
        ["subscribe", "publish", "float64", "uint8", "bool", "geometry_msgs/TwistStamped",
         "std_msgs/Float64", "/a", "/landshark/gps_velocity", "twist.linear.x", "data",
         "Controller", "Controller_U", "In1", "Out1", "pose.covariance[35]"]
    ),
)
TREES = st.recursive(
    SCALARS,
    lambda children: st.one_of(
        st.lists(children, max_size=5),
        st.dictionaries(st.one_of(st.sampled_from(KEYS), st.text(max_size=8)), children, max_size=6),
    ),
    max_leaves=40,
)


@FUZZ
@given(st.dictionaries(st.sampled_from(KEYS), TREES, max_size=6))
def test_arbitrary_yaml_trees(tree):
    load_or_invalid(_write(yaml.safe_dump(tree, allow_unicode=True).encode("utf-8")))


@FUZZ
@given(TREES)
def test_arbitrary_yaml_values(tree):
    load_or_invalid(_write(yaml.safe_dump(tree, allow_unicode=True).encode("utf-8")))


# --------------------------------------------------------------------------
# Strategy 3: mutations of valid models


def _paths(obj, prefix=()):
    yield prefix
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield from _paths(v, prefix + (k,))
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            yield from _paths(v, prefix + (i,))


def _get(obj, path):
    for k in path:
        obj = obj[k]
    return obj


@st.composite
def mutated(draw, base):
    data = copy.deepcopy(base)
    for _ in range(draw(st.integers(min_value=1, max_value=3))):
        paths = [p for p in _paths(data) if p]
        if not paths:
            break
        path = draw(st.sampled_from(paths))
        parent = _get(data, path[:-1])
        key = path[-1]
        op = draw(st.sampled_from(["drop", "replace", "replace", "dup", "rename", "swap"]))
        if op == "drop":
            del parent[key]
        elif op == "replace":
            parent[key] = draw(st.one_of(SCALARS, TREES))
        elif op == "dup" and isinstance(parent, list):
            parent.insert(key, copy.deepcopy(parent[key]))
        elif op == "rename" and isinstance(parent, dict):
            parent[draw(st.one_of(st.sampled_from(KEYS), st.text(max_size=6)))] = parent.pop(key)
        elif op == "swap":
            other = draw(st.sampled_from(paths))
            try:
                parent[key] = copy.deepcopy(_get(data, other))
            except (KeyError, IndexError, TypeError):
                pass
    return data


@FUZZ
@given(mutated(LS_DATA))
def test_mutated_landshark(data):
    load_or_invalid(_write(yaml.safe_dump(data, allow_unicode=True).encode("utf-8")))


@FUZZ
@given(mutated(MULTI_DATA))
def test_mutated_multi(data):
    load_or_invalid(_write(yaml.safe_dump(data, allow_unicode=True).encode("utf-8")))


@FUZZ
@given(st.data())
def test_text_mutations_of_landshark(data):
    lines = LS_TEXT.split("\n")
    for _ in range(data.draw(st.integers(min_value=1, max_value=3))):
        i = data.draw(st.integers(min_value=0, max_value=len(lines) - 1))
        op = data.draw(st.sampled_from(["delete", "insert", "edit", "indent"]))
        if op == "delete":
            del lines[i]
        elif op == "insert":
            lines.insert(i, data.draw(st.text(max_size=30)))
        elif op == "indent":
            lines[i] = " " + lines[i]
        else:
            j = data.draw(st.integers(min_value=0, max_value=len(lines[i])))
            lines[i] = lines[i][:j] + data.draw(st.text(max_size=3)) + lines[i][j + 1:]
        if not lines:
            break
    load_or_invalid(_write("\n".join(lines).encode("utf-8", errors="surrogatepass")))


def test_mutations_do_find_valid_and_invalid_models():
    """The mutation strategy is not vacuous: some mutants load, most fail."""
    rnd = random.Random(7)
    outcomes = set()
    for seed in range(300):
        data = copy.deepcopy(LS_DATA)
        path = rnd.choice([p for p in _paths(data) if p])
        parent = _get(data, path[:-1])
        if rnd.random() < 0.5:
            del parent[path[-1]]
        else:
            parent[path[-1]] = rnd.choice([None, 0, 1, 20, "x", "float64", "In1", [], {}])
        outcomes.add(load_or_invalid(_write(yaml.safe_dump(data).encode())) is None)
    assert outcomes == {True, False}


# --------------------------------------------------------------------------
# The command line never crashes


@FUZZ
@given(st.one_of(mutated(LS_DATA), st.dictionaries(st.sampled_from(KEYS), TREES, max_size=5)))
def test_cli_in_process(data):
    cli_exits_0_or_1(_write(yaml.safe_dump(data, allow_unicode=True).encode("utf-8")))


@FUZZ
@given(st.binary(max_size=500))
def test_cli_in_process_bytes(data):
    cli_exits_0_or_1(_write(data))


@pytest.mark.parametrize("seed", range(6))
def test_cli_subprocess(tmp_path, seed):
    rnd = random.Random(seed)
    if seed == 0:
        data = LS_TEXT.encode()
    elif seed == 1:
        data = bytes(rnd.randrange(256) for _ in range(300))
    else:
        tree = copy.deepcopy(LS_DATA)
        for _ in range(seed):
            path = rnd.choice([p for p in _paths(tree) if p])
            parent = _get(tree, path[:-1])
            parent[path[-1]] = rnd.choice([None, -1, "a b", "ψ", [1], {"k": 2}])
        data = yaml.safe_dump(tree, allow_unicode=True).encode()
    p = tmp_path / "m.yaml"
    p.write_bytes(data)
    env = dict(os.environ)
    env.pop("PYROSGEN_DEBUG", None)
    proc = subprocess.run(
        [sys.executable, "-m", "pyrosgen", "check", str(p)],
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
    )
    assert proc.returncode == (0 if seed == 0 else 1), proc.stderr
    assert "Traceback" not in proc.stderr
    if proc.returncode:
        assert proc.stdout == ""
        assert all(DIAG.match(line) for line in proc.stderr.splitlines()), proc.stderr
