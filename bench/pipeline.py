"""Benchmark 1: how fast ``pyrosgen generate`` makes proven glue, and how it
scales with the number N of relations (BENCHMARKS.md, section 1).

For each model (LandShark, and ``bench/synth.py`` nodes with N relations):

- ``cli``: the end-to-end command ``pyrosgen generate MODEL -o DIR -q``
  (wall time, and CPU time of the whole process tree);
- ``phases``: the same pipeline run in-process
  (:func:`pyrosgen.generate.generate`) with a driver that runs every tool
  under ``/usr/bin/time``, giving each tool's wall time, CPU time and peak
  memory (coqc on the per-node file, coqchk, the extraction's coqc,
  ocamlopt, the printer), and the phase times the pipeline reports
  (front end, coqc, checking, printing);
- ``validation``: the printer validation (:mod:`pyrosgen.verify.printer_validation`) on
  the printed files, timed on its own;
- ``gcc``: ``gcc -O2 -c`` of the printed glue;
- with ``--profile``: ``coqc -time`` on the per-node file, the slowest
  commands.

Each model is run ``repeat`` times; the median of each figure is kept.
The load average is recorded next to every run.
"""

from __future__ import annotations

import os
import re
import shutil
import sys
import time
from pathlib import Path

from common import PYROSGEN, REPO, WORK, Proc, loadavg, median, read_time_file, run, time_wrap

sys.path.insert(0, str(REPO))

from pyrosgen.proof.coqdriver import CoqcResult, CoqDriver  # noqa: E402

LANDSHARK = REPO / "examples" / "landshark" / "landshark_controller.yaml"


class TimedDriver(CoqDriver):
    """A :class:`CoqDriver` that runs every tool under ``/usr/bin/time`` and
    records ``(label, wall, user, sys, maxrss_kb)`` for each run."""

    def __init__(self, *a, **kw):
        super().__init__(*a, **kw)
        self.records: list[dict] = []

    @staticmethod
    def label(argv) -> str:
        tool = Path(argv[0]).name
        if tool == "coqc":
            return "extraction (coqc)" if any(str(a).endswith("Extract.v") for a in argv) else "coqc"
        if tool in ("ocamlfind", "ocamlopt", "ocamlc", "ocamlopt.opt", "ocamlc.opt"):
            return "ocaml compile"
        if tool == "print_job":
            return "printer run"
        return tool

    def run(self, argv, cwd):  # noqa: D102 - same contract as CoqDriver.run
        tf = Path(cwd) / f".bench-time-{len(self.records)}"
        res = super().run(time_wrap([str(a) for a in argv], tf), cwd)
        rec = {"tool": self.label(argv), "wall": res.seconds, "user": 0.0, "sys": 0.0, "maxrss_kb": 0}
        try:
            w, u, s, m = read_time_file(tf)
            rec.update(wall=w, user=u, sys=s, maxrss_kb=m)
            tf.unlink()
        except (OSError, IndexError, ValueError):
            pass
        self.records.append(rec)
        # /usr/bin/time adds "Command exited with non-zero status" lines to
        # its -o file only, so the tool's own output is unchanged.
        return CoqcResult(tuple(argv), res.returncode, res.stdout, res.stderr, res.seconds)


def _coq_profile(vfile: Path, lib_dir: Path, theories: Path, top: int = 8) -> list[dict]:
    """``coqc -time`` on the per-node file: the slowest commands."""
    p = run(["coqc", "-time", "-R", theories, "ROSGen", "-R", lib_dir, "RosgenNode", vfile.name],
            cwd=vfile.parent, check=False)
    rows = []
    for ln in p.stdout.splitlines():
        m = re.match(r"^Chars (\d+) - (\d+) \[(.*)\] ([\d.]+) secs \(([\d.]+)u,([\d.]+)s\)", ln)
        if m:
            rows.append({"command": m.group(3).replace("~", " ")[:60], "wall": float(m.group(4)),
                         "cpu": float(m.group(5)) + float(m.group(6)), "chars": int(m.group(2)) - int(m.group(1))})
    rows.sort(key=lambda r: -r["wall"])
    return rows[:top]


def one_run(model: Path, out: Path, env: dict, *, profile: bool) -> dict:
    """One in-process run of the pipeline with the timed driver, then gcc
    and validation on its output, and (optionally) the Coq profile."""
    from pyrosgen.generate import generate

    theories = Path(env["PYROSGEN_COQLIB"])
    drv = TimedDriver(theories)
    if out.exists():
        shutil.rmtree(out)
    out.parent.mkdir(parents=True, exist_ok=True)  # the work directory goes next to out
    la = loadavg()
    t0 = time.monotonic()
    res = generate(model, out, driver=drv, keep_work=profile)
    total = time.monotonic() - t0
    rec: dict = {"load": la, "total": total, "phases": dict(res.times), "tools": drv.records}
    name = res.model.name
    # gcc on the glue
    glue = out / f"{name}_glue.c"
    g = run(["gcc", "-std=c99", "-O2", "-c", glue.name, "-o", "/dev/null"], cwd=out)
    rec["gcc"] = {"wall": g.wall, "cpu": g.cpu, "maxrss_kb": g.maxrss_kb}
    rec["glue_bytes"] = glue.stat().st_size
    rec["glue_lines"] = glue.read_text().count("\n")
    # printer validation, timed on its own
    try:
        from pyrosgen.verify.printer_validation import validate_glue
    except ImportError:
        rec["validation"] = None
    else:
        t1 = time.monotonic()
        c1 = os.times()
        validate_glue(glue.read_text(), (out / f"{name}_types.h").read_text(), (out / f"{name}.sexp").read_text(),
                      glue_name=glue.name, header_name=f"{name}_types.h")
        c2 = os.times()
        rec["validation"] = {"wall": time.monotonic() - t1, "cpu": (c2.user - c1.user) + (c2.system - c1.system)}
    if profile:
        work = sorted(out.parent.glob(f".pyrosgen-{name}-*"), key=lambda p: p.stat().st_mtime)
        if work:
            wdir = work[-1]
            vfile = wdir / "coq" / f"{name}.v"
            if vfile.is_file():
                rec["coq_profile"] = _coq_profile(vfile, vfile.parent, theories)
                rec["vo_bytes"] = vfile.with_suffix(".vo").stat().st_size
                rec["v_bytes"] = vfile.stat().st_size
                job = vfile.parent / "job.ml"
                if job.is_file():
                    rec["job_ml_bytes"] = job.stat().st_size
            for w in work:
                shutil.rmtree(w, ignore_errors=True)
    return rec


def cli_run(model: Path, out: Path, env: dict) -> dict:
    """``pyrosgen generate`` as a user runs it."""
    if out.exists():
        shutil.rmtree(out)
    la = loadavg()
    p: Proc = run([PYROSGEN, "generate", model, "-o", out, "-q"], env=env, timeout=1800)
    return {"load": la, "wall": p.wall, "cpu": p.cpu, "maxrss_kb": p.maxrss_kb}


def bench_model(label: str, n: int | None, model: Path, env: dict, repeat: int, *, profile: bool, log) -> dict:
    runs, clis = [], []
    out = WORK / "pipeline" / label
    for i in range(repeat):
        r = one_run(model, out / "inproc", env, profile=profile and i == 0)
        runs.append(r)
        c = cli_run(model, out / "cli", env)
        clis.append(c)
        log(f"  {label} run {i + 1}/{repeat}: cli {c['wall']:.2f} s (cpu {c['cpu']:.2f} s), in-process "
            f"{r['total']:.2f} s [{', '.join(f'{k} {v:.2f}' for k, v in r['phases'].items())}] load {r['load']}")

    def med(f):
        vals = [f(r) for r in runs]
        vals = [v for v in vals if v is not None]
        return median(vals) if vals else None

    tools: dict[str, dict] = {}
    for r in runs:
        for t in r["tools"]:
            d = tools.setdefault(t["tool"], {"wall": [], "cpu": [], "maxrss_kb": []})
            d["wall"].append(t["wall"])
            d["cpu"].append(t["user"] + t["sys"])
            d["maxrss_kb"].append(t["maxrss_kb"])
    phases = {k: med(lambda r, k=k: r["phases"].get(k)) for k in runs[0]["phases"]}
    summary = {
        "label": label,
        "n": n,
        "model": str(model.relative_to(REPO)) if model.is_relative_to(REPO) else str(model),
        "repeat": repeat,
        "loads": [r["load"] for r in runs] + [c["load"] for c in clis],
        "cli_wall": median([c["wall"] for c in clis]),
        "cli_cpu": median([c["cpu"] for c in clis]),
        # the load of other jobs only ever adds time: the best run is the
        # estimate of the pipeline's own cost, the median is shown too
        "cli_wall_min": min(c["wall"] for c in clis),
        "cli_cpu_min": min(c["cpu"] for c in clis),
        "cli_runs": [{"wall": c["wall"], "cpu": c["cpu"], "load": c["load"]} for c in clis],
        "phases_min": {k: min(r["phases"][k] for r in runs if k in r["phases"]) for k in runs[0]["phases"]},
        "cli_maxrss_kb": max(c["maxrss_kb"] for c in clis),
        "inproc_total": med(lambda r: r["total"]),
        "phases": phases,
        "tools": {k: {"wall": median(v["wall"]), "cpu": median(v["cpu"]), "maxrss_kb": max(v["maxrss_kb"])}
                  for k, v in tools.items()},
        "gcc": {"wall": med(lambda r: r["gcc"]["wall"]), "cpu": med(lambda r: r["gcc"]["cpu"])},
        "validation": None if runs[0]["validation"] is None else {
            "wall": med(lambda r: r["validation"]["wall"]), "cpu": med(lambda r: r["validation"]["cpu"])},
        "glue_bytes": runs[0]["glue_bytes"],
        "glue_lines": runs[0]["glue_lines"],
    }
    for k in ("coq_profile", "vo_bytes", "v_bytes", "job_ml_bytes"):
        if k in runs[0]:
            summary[k] = runs[0][k]
    summary["load1_min"] = min(float(x.split()[0]) for x in summary["loads"])
    return summary


#: The per-node file's acceptance lemmas as they were before the fixes of
#: BENCHMARKS.md (coq/templates/node.v.j2 at commit f7b0efe): [generate]
#: run to the end by vm_compute, the program included.
_BEFORE_LEMMAS = """\
Definition accepted (r : res program) : bool :=
  match r with OK _ => true | Error _ => false end.
Definition refusal (r : res program) : string :=
  match r with OK _ => "" | Error msg => string_of_errmsg msg end.

Lemma generate_accepts : accepted program_result = true.
Proof.
  vm_compute.
  lazymatch goal with
  | |- true = true => reflexivity
  | _ => let msg := eval vm_compute in (refusal program_result) in
         fail 0 "ROSGen.Generator.generate refused the model:" msg
  end.
Qed.

Lemma generate_ok : Generator.generate model = OK the_program.
Proof.
  generalize generate_accepts; unfold the_program, program_of, accepted, program_result.
  destruct (Generator.generate model) as [p|msg]; intro ACCEPTS;
    [reflexivity | discriminate ACCEPTS].
Qed.

"""


def before_fixes(text: str) -> str:
    """The per-node file as the template made it before the fixes: the old
    acceptance lemmas, and no extraction (so that the driver extracts with a
    second coqc)."""
    i = text.find("(** [generate] accepts the model")
    j = text.find("(** ** Theorems about this node *)")
    if i < 0 or j < 0:
        raise RuntimeError("bench: the per-node file does not have the expected shape (update pipeline.py)")
    text = text[:i] + _BEFORE_LEMMAS + text[j:]
    k = text.find("(** ** Extraction of the printed texts *)")
    return text[:k].rstrip() + "\n" if k >= 0 else text


def ab(model: Path, label: str, env: dict, runs: int, log) -> dict:
    """The fixes measured in the same run: the pipeline as it was before
    them (:func:`before_fixes`, and ocamlopt always) and as it is,
    alternated, in-process; wall time and CPU time (this process and its
    children)."""
    import pyrosgen.proof.coqdriver as cd
    import pyrosgen.generate as gen

    orig_render, orig_max = gen.render_node_file, cd.BYTECODE_MAX_BYTES

    def old_render(*a, **kw):
        return before_fixes(orig_render(*a, **kw))

    out = {v: {"wall": [], "cpu": [], "coqc": [], "printing": []} for v in ("before", "after")}
    la = loadavg()
    theories = Path(env["PYROSGEN_COQLIB"])
    dest = WORK / "pipeline" / f"ab_{label}" / "out"
    dest.parent.mkdir(parents=True, exist_ok=True)
    try:
        for i in range(runs):
            for variant in (("before", "after") if i % 2 == 0 else ("after", "before")):
                gen.render_node_file = old_render if variant == "before" else orig_render
                cd.BYTECODE_MAX_BYTES = 0 if variant == "before" else orig_max
                if dest.exists():
                    shutil.rmtree(dest)
                c0, t0 = os.times(), time.monotonic()
                res = gen.generate(model, dest, driver=CoqDriver(theories))
                c1, t1 = os.times(), time.monotonic()
                cpu = (c1.user - c0.user) + (c1.system - c0.system) + (c1.children_user - c0.children_user) \
                    + (c1.children_system - c0.children_system)
                o = out[variant]
                o["wall"].append(t1 - t0)
                o["cpu"].append(cpu)
                o["coqc"].append(res.times.get("coqc", float("nan")))
                o["printing"].append(res.times.get("printing", float("nan")))
                log(f"  A/B {label} {variant}: {t1 - t0:.2f} s wall, {cpu:.2f} s CPU, coqc "
                    f"{o['coqc'][-1]:.2f} s, printing {o['printing'][-1]:.2f} s")
    finally:
        gen.render_node_file, cd.BYTECODE_MAX_BYTES = orig_render, orig_max
    return {"label": label, "runs": runs, "load": la + " / " + loadavg(),
            "before": {k: median(v) for k, v in out["before"].items()},
            "after": {k: median(v) for k, v in out["after"].items()},
            "before_min": {k: min(v) for k, v in out["before"].items()},
            "after_min": {k: min(v) for k, v in out["after"].items()}}


def run_pipeline(env: dict, *, quick: bool, log) -> dict:
    """All models; returns the results (also for the report)."""
    import synth

    sizes = [4, 40, 400] if quick else [4, 40, 400, 2000]
    models: list[tuple[str, int | None, Path]] = [("landshark", 4, LANDSHARK)]
    for n in sizes:
        d = WORK / "models" / f"synth_{n}"
        models.append((f"synth_{n}", n, synth.write(n, d)))
    results = []
    for label, n, path in models:
        repeat = 1 if quick else (2 if (n or 0) >= 2000 else 3)
        log(f"pipeline: {label} ({repeat} run(s))")
        results.append(bench_model(label, n, path, env, repeat, profile=not quick or label == "landshark", log=log))
    log("pipeline: A/B of the fixes (LandShark, N = 400)")
    abs_ = [ab(LANDSHARK, "landshark", env, 2 if quick else 4, log)]
    if "synth_400" in {r["label"] for r in results}:
        abs_.append(ab(WORK / "models" / "synth_400" / "synth_400.yaml", "synth_400", env, 1 if quick else 2, log))
    by = {r["label"]: r for r in results}
    ratios = {}
    if "synth_400" in by and "synth_2000" in by:
        ratios["cli t(2000)/t(400)"] = by["synth_2000"]["cli_wall_min"] / by["synth_400"]["cli_wall_min"]
        ratios["cli cpu(2000)/cpu(400)"] = by["synth_2000"]["cli_cpu_min"] / by["synth_400"]["cli_cpu_min"]
    if "synth_40" in by and "synth_400" in by:
        ratios["cli t(400)/t(40)"] = by["synth_400"]["cli_wall_min"] / by["synth_40"]["cli_wall_min"]
    return {"models": results, "ratios": ratios, "ab": abs_}
