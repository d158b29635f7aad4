"""Helpers shared by the tests of ``pyrosgen generate`` (the per-node Coq
file, the Coq driver and the pipeline)."""

from __future__ import annotations

import os
import re
import subprocess
from pathlib import Path

from pyrosgen.proof.coqdriver import DEFAULT_THEORIES, CoqDriver

HERE = Path(__file__).resolve().parents[1] / "generate"
REPO = HERE.parents[1]
GOLDEN = HERE / "golden"
MODELS = HERE / "models"
LANDSHARK = REPO / "examples" / "landshark" / "landshark_controller.yaml"
MULTI = REPO / "examples" / "multi" / "multi_node.yaml"
COQPROJECT = REPO / "coq" / "_CoqProject"

GCC_STRICT = ["gcc", "-std=c11", "-Wall", "-Wextra", "-Werror", "-pedantic"]

def _uses_freshness(path: Path) -> bool:
    """Whether the model uses rule 4.12 (timeouts, derived inputs; not the
    ``derived: length`` and ``truncated`` of rule 4.15, which are ordinary
    input relations)."""
    text = path.read_text(encoding="utf-8")
    return "timeout_ms" in text or re.search(r"derived:\s*(?:is_new|received|age_ms)\b", text) is not None


#: Every model that the front end must accept and Coq's generate too
#: (rule 4.12's timeouts and derived inputs included: they are generated).
OK_MODELS = sorted(
    p for p in {*(REPO / "tests" / "frontend" / "models").glob("ok_*.yaml"),
                *(REPO / "examples").glob("*/*.yaml"),
                *MODELS.glob("ok_*.yaml")}
    # a system file (DESIGN.md section 10: top-level key system) is not a node model
    if not re.search(r"^system:", p.read_text(encoding="utf-8"), re.M)
)

#: The models of :data:`OK_MODELS` that use rule 4.12 (timed topics).
FRESHNESS_MODELS = [p for p in OK_MODELS if _uses_freshness(p)]


def ddc_in_coqproject() -> bool:
    """Whether ``coq/_CoqProject`` lists the node DDC theorem's files."""
    lines = [ln.split("#", 1)[0].strip() for ln in COQPROJECT.read_text().splitlines()]
    names = {Path(ln).name for ln in lines if ln.startswith("theories/")}
    return "Loopproof.v" in names and "DDC.v" in names


def run(cmd: list[str], cwd: Path | None = None, timeout: int = 900, env=None) -> subprocess.CompletedProcess:
    """Run a command; raise with its output if it fails."""
    proc = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=timeout, check=False, env=env)
    if proc.returncode != 0:
        raise AssertionError(
            f"command failed ({proc.returncode}): {' '.join(map(str, cmd))}\n"
            f"--- stdout ---\n{proc.stdout}\n--- stderr ---\n{proc.stderr}"
        )
    return proc


def coqc(vfile: Path, lib: str = "T", check: bool = True) -> subprocess.CompletedProcess:
    """Compile ``vfile`` against the ROSGen library (``-R <dir> <lib>``)."""
    cmd = ["coqc", "-R", str(DEFAULT_THEORIES), "ROSGen", "-R", str(vfile.parent), lib, vfile.name]
    if check:
        return run(cmd, cwd=vfile.parent)
    return subprocess.run(cmd, cwd=vfile.parent, capture_output=True, text=True, check=False, timeout=900)


_PRINTED_STRING = re.compile(r'^\s*=\s*"((?:[^"]|"")*)"\s*\n\s*:\s*(?:String\.)?string', re.M)


def printed_strings(output: str) -> list[str]:
    """The values printed by ``Eval vm_compute in <string>.`` commands, in order."""
    return [m.group(1).replace('""', '"') for m in _PRINTED_STRING.finditer(output)]


def require_library() -> None:
    """Fail (not skip) with the fix when the ROSGen library is not built."""
    CoqDriver().check_library()


def generate_with_tampered_node_file(model: Path, old: str, new: str, monkeypatch, capsys, out: Path,
                                     count: int = 1):
    """``pyrosgen generate model -o out`` with ``old`` replaced by ``new``
    (``count`` times, every time if -1) in the per-node Coq file it
    writes (``old`` must be there): the exit code and the standard
    error."""
    import pyrosgen.generate as gen
    from pyrosgen import cli

    original = gen.render_node_file

    def tampered(model, **kw):
        text = original(model, **kw)
        assert old in text
        return text.replace(old, new, count)

    monkeypatch.setattr(gen, "render_node_file", tampered)
    code = cli.main(["generate", str(model), "-o", str(out), "-q"])
    return code, capsys.readouterr().err


def make_standin_library(dest: Path, *, drop: tuple[str, ...] = (), extra: dict[str, str] | None = None) -> Path:
    """A copy of the ROSGen library in ``dest/theories`` made of symbolic
    links to the real compiled files, whose ``_CoqProject`` omits the
    modules in ``drop``; each ``extra`` module (name -> Coq source) is
    written and compiled there instead.  The layer folders are kept (the
    compiled files are ``ROSGen.<layer>.<Name>``); ``Main``, which depends on
    every module, is left out too when anything is dropped.  Returns the
    theories directory."""
    theories = dest / "theories"
    theories.mkdir(parents=True)
    listed = []
    for line in COQPROJECT.read_text().splitlines():
        entry = line.split("#", 1)[0].strip()
        if entry.startswith("theories/") and entry.endswith(".v"):
            rel = Path(entry).relative_to("theories")
            name = rel.stem
            if name in drop or (extra and name in extra) or (drop and name == "Main"):
                continue
            listed.append(entry)
            (theories / rel.parent).mkdir(parents=True, exist_ok=True)
            for suffix in (".v", ".vo"):
                os.symlink(DEFAULT_THEORIES / rel.with_suffix(suffix), theories / rel.with_suffix(suffix))
    for name, text in (extra or {}).items():
        (theories / f"{name}.v").write_text(text)
        run(["coqc", "-R", str(theories), "ROSGen", f"{name}.v"], cwd=theories)
        listed.append(f"theories/{name}.v")
    (dest / "_CoqProject").write_text("-R theories ROSGen\n" + "\n".join(listed) + "\n")
    return theories


def difftest_sides(out: Path, node: str, work: Path, mutant: str | None = None) -> dict:
    """The sides of the differential test of the folder ``out`` that
    ``pyrosgen generate`` wrote for ``node``, built in ``work``: ``dump``
    (the node's dump, ``<node>.sexp``), ``c`` (the glue and the harness
    under gcc -O2), ``c_san`` (under the sanitizers), ``coq`` (the Coq
    interpreter of the per-node file) and, when ``mutant`` names one of
    the harness's conversions (:data:`pyrosgen.verify.difftest.CLAMPS`),
    ``c_mutant``: the glue under gcc -O2 with that harness, which a test
    must catch."""
    from pyrosgen.verify.difftest import NodeDump, build_c_harness, build_coq_runner

    sides = {
        "dump": NodeDump.from_text((out / f"{node}.sexp").read_text()),
        "c": build_c_harness(out, node, work, opt="-O2"),
        "c_san": build_c_harness(out, node, work, sanitize=True),
    }
    if mutant is not None:
        sides["c_mutant"] = build_c_harness(out, node, work, opt="-O2", name=f"{node}_{mutant}", clamp=mutant)
    sides["coq"] = build_coq_runner(out, node, work)
    return sides


def sides_agree(sides: dict, sched: str) -> str:
    """The trace that the Coq interpreter prints for the schedule
    ``sched`` (``sides["coq"]``), after checking that the glue under
    gcc -O2 (``sides["c"]``) and under the sanitizers (``sides["c_san"]``)
    print the same, byte for byte."""
    from pyrosgen.verify.difftest import run_side

    coq = run_side(sides["coq"], sched)
    assert run_side(sides["c"], sched) == coq
    assert run_side(sides["c_san"], sched) == coq
    return coq

