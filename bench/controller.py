"""Block-diagram controllers: the cost of the generated step, and of
generating it (BENCHMARKS.md, section "Block-diagram controllers: step cost
by input regime, generation up to the block limit").

- **Instructions per ``Controller_step``**, counted exactly by callgrind
  (``--toggle-collect=Controller_step``: only instructions executed while
  the step function is on the stack, its callees included), for the C that
  pyrosgen generates from examples/landshark/landshark_diagram.yaml and for
  the hand-written Embedded-Coder-style controller
  examples/landshark/controller/Controller.c.  Both are compiled as
  ``pyrosgen build`` compiles a controller (``gcc -std=c11`` and
  ``pyrosgen.ros.build.CONTROLLER_CFLAGS``: ``-O2``), each as its own
  translation unit, and linked with one harness that steps them on a table
  of readings (the same table for both).  Per step = (count at 2N steps -
  count at N steps) / N, N = 10,000, so nothing outside the steps counts.
  Four input regimes, because both controllers branch on the readings:
  *nominal* (three readings within ±0.02 m/s of a slowly varying speed),
  *spoofed* (one reading in ten replaced by 4.5 m/s), *faulty* (one in four
  a NaN or an infinity), and *mixed* (nominal, with 5 % spoofed and 1 %
  faulty readings).  Goal: generated / hand-written <= 1.2.
- **``pyrosgen generate`` wall time** (and CPU, peak memory, and the
  phases the CLI reports): LandShark with its diagram (median of 5), and
  synthetic LandShark nodes whose diagram is a chain of ``n`` Gain and Sum
  blocks over the three inputs (n = 200 and 1,000: median of 3; n = 4,000
  and 5,000, the limit of rule 4.11: one run; a run that fails is
  recorded, and run again under ``ulimit -s unlimited``).  Goals: 1,000 blocks <= 60 s, growth
  from 200 to 1,000 blocks at most linear (t(1000) / t(200) <= 5).

The two controllers are not the same function: the hand-written one orders
a NaN above every number and updates its integrator before using it, the
diagram takes the state at the start of the step (see the comment in
landshark_diagram.yaml); they implement the same law, and this benchmark
compares their cost only.

usage: .venv/bin/python bench/controller.py [--revision REV | --checkout [--coqlib THEORIES]]
       [--runs 5] [--sizes 200,1000,4000,5000] [--no-generate]
By default it measures a snapshot of HEAD (``git archive``, its library
built once into build/bench/controller-src-<commit>/), not the shared
checkout, which others may be editing and rebuilding during the run.
writes bench/results/controller.json and prints the BENCHMARKS.md section.
"""

from __future__ import annotations

import argparse
import math
import os
import random
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import PY, REPO, WORK, load_json, loadavg, machine, run, save_json  # noqa: E402

from pyrosgen.frontend.validate import load_model  # noqa: E402
from pyrosgen.ros.build import CONTROLLER_CFLAGS  # noqa: E402

STEPS = 10_000
TABLE = 1000
DIAGRAM = REPO / "examples" / "landshark" / "landshark_diagram.yaml"
HANDWRITTEN = REPO / "examples" / "landshark" / "controller"
REGIMES = ("nominal", "spoofed", "faulty", "mixed")
CFLAGS = ("-std=c11", *CONTROLLER_CFLAGS)

HARNESS = r"""/* bench/controller.py: steps a LandShark controller on a table of readings. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>

struct U3 { double In1, In2, In3; };
struct Y1 { double Out1; };
extern struct U3 Controller_U;
extern struct Y1 Controller_Y;
void Controller_initialize(void);
void Controller_step(void);

static const double table[%(n)d][3] = {
%(rows)s
};

int main(int argc, char **argv)
{
    long steps = argc > 1 ? atol(argv[1]) : %(steps)d;
    unsigned long long sum = 0;
    Controller_initialize();
    for (long i = 0; i < steps; i++) {
        const double *r = table[i %% %(n)d];
        Controller_U.In1 = r[0];
        Controller_U.In2 = r[1];
        Controller_U.In3 = r[2];
        Controller_step();
        { unsigned long long b; memcpy(&b, &Controller_Y.Out1, sizeof b); sum += b; }
    }
    printf("%%llu\n", sum);
    return 0;
}
"""


# ---------------------------------------------------------------------------
# Inputs


def _c_double(x: float) -> str:
    if math.isnan(x):
        return "NAN"
    if math.isinf(x):
        return "INFINITY" if x > 0 else "-INFINITY"
    return x.hex()


def readings(regime: str, seed: int = 2026) -> list[tuple[float, float, float]]:
    """``TABLE`` rows of three readings (m/s) for ``regime``."""
    rng = random.Random(f"{seed}-{regime}")
    rows = []
    for i in range(TABLE):
        v = 1.0 + 0.3 * math.sin(i / 50.0)
        r = [v + rng.uniform(-0.02, 0.02) for _ in range(3)]
        k = rng.randrange(3)
        p = rng.random()
        if regime == "spoofed" and i % 10 == 0:
            r[k] = 4.5
        elif regime == "faulty" and i % 4 == 0:
            r[k] = rng.choice([math.nan, math.inf, -math.inf])
        elif regime == "mixed":
            if p < 0.05:
                r[k] = 4.5
            elif p < 0.06:
                r[k] = rng.choice([math.nan, math.inf, -math.inf])
        rows.append((r[0], r[1], r[2]))
    return rows


def harness_source(regime: str) -> str:
    rows = ",\n".join("    {" + ", ".join(_c_double(x) for x in row) + "}" for row in readings(regime))
    return HARNESS % {"n": TABLE, "rows": rows, "steps": STEPS}


# ---------------------------------------------------------------------------
# Instructions


def _collected(outfile: Path) -> int:
    """The instructions a callgrind run collected (``totals:`` line)."""
    for ln in outfile.read_text().splitlines():
        m = re.match(r"^(?:totals|summary):\s+(\d+)", ln)
        if m:
            return int(m.group(1))
    raise RuntimeError(f"no totals in {outfile}")


def step_function_bytes(obj: Path) -> int:
    """The size of ``Controller_step``'s machine code in an object file."""
    out = run(["nm", "-S", str(obj)]).stdout
    for ln in out.splitlines():
        parts = ln.split()
        if len(parts) == 4 and parts[3] == "Controller_step":
            return int(parts[1], 16)
    raise RuntimeError(f"no Controller_step in {obj}")


def instructions(work: Path, label: str, controller_c: Path, includes: list[Path]) -> dict:
    """Per regime: instructions per ``Controller_step`` of ``controller_c``,
    and the output checksum of the run (so that both controllers are seen
    to run the same table)."""
    inc = [a for i in includes for a in ("-I", str(i))]
    obj = work / f"{label}.o"
    run(["gcc", *CFLAGS, *inc, "-c", str(controller_c), "-o", str(obj)])
    res: dict = {"code_bytes": step_function_bytes(obj), "regimes": {}}
    for regime in REGIMES:
        h = work / f"harness_{regime}.c"
        h.write_text(harness_source(regime))
        hobj = work / f"harness_{regime}.o"
        run(["gcc", "-std=c11", "-O2", "-c", str(h), "-o", str(hobj)])
        exe = work / f"{label}_{regime}"
        run(["gcc", str(hobj), str(obj), "-o", str(exe), "-lm"])
        counts = {}
        for n in (STEPS, 2 * STEPS):
            out = work / f"callgrind.{label}.{regime}.{n}"
            run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}",
                 "--toggle-collect=Controller_step", str(exe), str(n)], timeout=600)
            counts[n] = _collected(out)
        res["regimes"][regime] = {
            "per_step": (counts[2 * STEPS] - counts[STEPS]) / STEPS,
            "count_n": counts[STEPS], "count_2n": counts[2 * STEPS],
        }
    return res


# ---------------------------------------------------------------------------
# Generation time


def synthetic(n: int, path: Path) -> None:
    """LandShark with a diagram that is a chain of ``n`` blocks: Gains by
    0.5 and Sums ``prev - In_k``, cycling over the three inputs."""
    text = DIAGRAM.read_text()
    head = text.split("  blocks:")[0]
    tail = text.split("  outports:")[1].split("\n", 1)[1]
    blocks, prev = [], "In1"
    for i in range(n):
        if i % 2 == 0:
            blocks.append(f"    - {{name: g{i}, block: Gain, input: {prev}, gain: 0.5}}")
            prev = f"g{i}"
        else:
            blocks.append(f"    - {{name: s{i}, block: Sum, inputs: [{prev}, In{1 + i % 3}], signs: \"+-\"}}")
            prev = f"s{i}"
    path.write_text(head + "  blocks:\n" + "\n".join(blocks) + f"\n  outports: {{Out1: {prev}}}\n" + tail)


_PHASES = re.compile(r"time\s+front end ([\d.]+) s, coqc ([\d.]+) s, checking ([\d.]+) s, printing ([\d.]+) s; "
                     r"total ([\d.]+) s")


def generate_once(model: Path, out: Path, env: dict, *, unlimited_stack: bool = False) -> dict:
    """One ``pyrosgen generate``; a failure is recorded (its last line),
    not raised.  ``unlimited_stack``: under ``ulimit -s unlimited``."""
    argv = [*PYROSGEN_CMD, "generate", str(model), "-o", str(out)]
    if unlimited_stack:
        argv = ["bash", "-c", 'ulimit -s unlimited && exec "$@"', "generate", *argv]
    p = run(argv, env=env, timeout=3600, check=False)
    if p.rc != 0:
        last = [ln for ln in (p.stdout + p.stderr).splitlines() if ln.strip()]
        return {"wall": p.wall, "cpu": p.cpu, "maxrss_mb": p.maxrss_kb / 1024, "phases": {},
                "failed": " / ".join(last[-2:]) if last else f"exit status {p.rc}"}
    m = _PHASES.search(p.stdout + p.stderr)
    phases = dict(zip(("front end", "coqc", "checking", "printing", "total"), map(float, m.groups()))) if m else {}
    return {"wall": p.wall, "cpu": p.cpu, "maxrss_mb": p.maxrss_kb / 1024, "phases": phases}


def generate_times(model: Path, runs: int, work: Path, env: dict, **kw) -> dict:
    rs = [generate_once(model, work / f"out{i}", env, **kw) for i in range(runs)]
    failed = [r["failed"] for r in rs if "failed" in r]
    if failed:
        return {"runs": rs, "failed": failed[0], "median_wall": statistics.median(r["wall"] for r in rs),
                "median_cpu": statistics.median(r["cpu"] for r in rs), "phases_of_median": {},
                "maxrss_mb": max(r["maxrss_mb"] for r in rs)}
    med = statistics.median(r["wall"] for r in rs)
    best = min(rs, key=lambda r: abs(r["wall"] - med))
    return {"runs": rs, "median_wall": med, "median_cpu": statistics.median(r["cpu"] for r in rs),
            "phases_of_median": best["phases"], "maxrss_mb": max(r["maxrss_mb"] for r in rs)}


# ---------------------------------------------------------------------------
# What is measured: a snapshot of a revision

#: ``pyrosgen`` as run by this benchmark (``python -m pyrosgen``, with the
#: snapshot first on ``PYTHONPATH``).
PYROSGEN_CMD = [str(PY), "-m", "pyrosgen"]


def snapshot(rev: str, log=print) -> tuple[Path, str]:
    """``git archive`` of revision ``rev`` in ``build/bench/``, its Coq
    library built (once per commit): the package and the library of one
    commit.  The checkout is shared: others edit and rebuild ``coq/`` while
    a benchmark runs (a run of this script once failed with coqchk's
    "Inconsistent assumptions over module ROSGen.ctrl.Diagram" when the
    checkout's library was rebuilt under it), and a half-edited library
    or template measures nothing.  Returns the folder and the commit."""
    commit = _git("rev-parse", rev)
    if not re.fullmatch(r"[0-9a-f]{40}", commit):
        raise SystemExit(f"bench/controller.py: unknown revision {rev!r}")
    dest = WORK / f"controller-src-{commit[:12]}"
    stamp = dest / ".bench-built"
    if not stamp.is_file():
        if dest.exists():
            import shutil

            shutil.rmtree(dest)
        dest.mkdir(parents=True)
        log(f"snapshot of {commit[:12]} in {dest}: building its Coq library")
        archive = subprocess.run(["git", "archive", commit], cwd=REPO, capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", str(dest)], input=archive, check=True)
        run(["make", "-C", str(dest / "coq"), "build", f"-j{os.cpu_count() or 1}"], timeout=3600)
        stamp.write_text(commit + "\n")
    return dest, commit


def _git(*args: str) -> str:
    try:
        return subprocess.run(["git", *args], cwd=REPO, capture_output=True, text=True, check=False).stdout.strip()
    except OSError:
        return "?"


def section(res: dict) -> str:
    """The BENCHMARKS.md section, from the results."""
    ins = res["instructions"]
    g, h = ins["generated"], ins["handwritten"]
    lines = [
        f"`bench/controller.py` (results in `bench/results/controller.json`), {res['date']}, "
        f"revision {res['revision']}, {res['machine']['cpu']}, {res['machine']['cores']} cores, "
        f"load {res['load_start']} → {res['load_end']}.",
        "",
        "Instructions per `Controller_step` (callgrind, exact; `gcc " + " ".join(CFLAGS) + "`, "
        f"each controller its own translation unit; (count at {2 * STEPS:,} steps − count at {STEPS:,}) / {STEPS:,}):",
        "",
        "| input regime | generated from the diagram | hand-written `Controller.c` | ratio | goal ≤ 1.2 |",
        "|---|---|---|---|---|",
    ]
    for r in REGIMES:
        a, b = g["regimes"][r]["per_step"], h["regimes"][r]["per_step"]
        lines.append(f"| {r} | {a:.1f} | {b:.1f} | {a / b:.2f} | {'met' if a / b <= 1.2 else '**missed**'} |")
    lines += [f"| code size of `Controller_step` (bytes) | {g['code_bytes']} | {h['code_bytes']} | "
              f"{g['code_bytes'] / h['code_bytes']:.2f} | |", ""]
    gen = res.get("generate")
    if gen:
        lines += ["`pyrosgen generate` (wall and CPU: medians; phases as the CLI reports them, of the median run):",
                  "",
                  "| model | blocks | runs | wall | CPU | coqc | checking | printing | peak memory | goal |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        for key, row in gen.items():
            ph = row["phases_of_median"]
            goal = ""
            if key == "chain_1000":
                goal = f"≤ 60 s: {'met' if row['median_wall'] <= 60 else '**missed**'}"
            if "failed" in row:
                why = re.sub(r"; nothing written to \S+", "", row["failed"]).replace("\\x0a", "").strip()
                lines.append(f"| {row['label']} | {row['blocks']} | {len(row['runs'])} | **failed** after "
                             f"{row['median_wall']:.2f} s: `{why}` | | | | | {row['maxrss_mb']:.0f} MB | |")
                continue
            lines.append(f"| {row['label']} | {row['blocks']} | {len(row['runs'])} | {row['median_wall']:.2f} s | "
                         f"{row['median_cpu']:.2f} s | {ph.get('coqc', 0):.2f} s | {ph.get('checking', 0):.2f} s | "
                         f"{ph.get('printing', 0):.2f} s | {row['maxrss_mb']:.0f} MB | {goal} |")
        if "chain_200" in gen and "chain_1000" in gen:
            t200, t1000 = gen["chain_200"]["median_wall"], gen["chain_1000"]["median_wall"]
            base = gen["landshark"]["median_wall"] if "landshark" in gen else 0.0
            nb = gen["landshark"]["blocks"] if "landshark" in gen else 0
            growth = t1000 / t200
            lines += ["", f"Growth from 200 to 1,000 blocks (5× the blocks): {growth:.2f}× the wall time "
                      f"(goal ≤ 5×, at most linear: {'met' if growth <= 5 else '**missed**'}).  Without the "
                      f"{base:.2f} s of LandShark's {nb}-block node, the part that depends on the blocks grows "
                      f"{(t1000 - base) / (t200 - base):.2f}× for {(1000 - nb) / (200 - nb):.2f}× the blocks: "
                      f"{1000 * (t200 - base) / (200 - nb):.1f} ms per block up to 200, "
                      f"{1000 * (t1000 - t200) / 800:.1f} ms per block from 200 to 1,000."]
            for key, row in gen.items():
                n = row["blocks"]
                if key.startswith("chain_") and n > 1000 and "failed" not in row:
                    lines.append(f"From 1,000 to {n:,} blocks ({row['label']}): "
                                 f"{row['median_wall'] / t1000:.2f}× the wall time "
                                 f"({1000 * (row['median_wall'] - t1000) / (n - 1000):.1f} ms per block).")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--revision", default="HEAD",
                    help="measure a snapshot of this commit (default HEAD; built once in build/bench/)")
    ap.add_argument("--checkout", action="store_true",
                    help="measure the checkout as it is instead (its pyrosgen and coq/theories, or --coqlib)")
    ap.add_argument("--coqlib", help="with --checkout: the compiled library's theories/")
    ap.add_argument("--runs", type=int, default=5, help="runs of generate on LandShark (default 5)")
    ap.add_argument("--sizes", default="200,1000,4000,5000",
                    help="synthetic chain sizes (default 200,1000,4000,5000)")
    ap.add_argument("--no-generate", action="store_true", help="only the instruction counts")
    ap.add_argument("--report-only", action="store_true", help="print the section from bench/results/controller.json")
    a = ap.parse_args(argv)
    if a.report_only:
        print(section(load_json("controller.json")))
        return 0
    env = {k: v for k, v in os.environ.items() if k != "PYROSGEN_COQLIB"}
    if a.checkout:
        env["PYTHONPATH"] = str(REPO)
        if a.coqlib:
            env["PYROSGEN_COQLIB"] = str(Path(a.coqlib).resolve())
        dirty = _git("status", "--porcelain", "--untracked-files=no", "--", "coq", "pyrosgen")
        revision = "the checkout at " + _git("rev-parse", "--short", "HEAD") + (
            " with uncommitted changes" if dirty else "")
    else:
        src, commit = snapshot(a.revision)
        env["PYTHONPATH"] = str(src)
        revision = commit[:7]
    for tool in ("valgrind", "gcc", "nm"):
        if subprocess.run(["which", tool], capture_output=True).returncode != 0:
            print(f"bench/controller.py: {tool} not found (apt-get install -y valgrind binutils gcc)", file=sys.stderr)
            return 2
    res: dict = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "load_start": loadavg(),
                 "revision": revision,
                 "machine": machine(), "steps": STEPS, "cflags": list(CFLAGS)}
    WORK.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="bench-controller-", dir=WORK) as tmp:
        work = Path(tmp)
        gen = work / "gen"
        run([*PYROSGEN_CMD, "generate", str(DIAGRAM), "-o", str(gen), "-q"], env=env, timeout=600)
        ins = {"generated": instructions(work, "generated", gen / "landshark_controller_controller.c", []),
               "handwritten": instructions(work, "handwritten", HANDWRITTEN / "Controller.c", [HANDWRITTEN])}
        res["instructions"] = ins
        for r in REGIMES:
            g, h = ins["generated"]["regimes"][r]["per_step"], ins["handwritten"]["regimes"][r]["per_step"]
            print(f"instructions per step, {r}: generated {g:.1f}, hand-written {h:.1f}, ratio {g / h:.2f}",
                  flush=True)
        if not a.no_generate:
            out: dict = {}
            t = generate_times(DIAGRAM, a.runs, work / "landshark", env)
            nb = len(load_model(DIAGRAM).controller.diagram.blocks)
            out["landshark"] = {"label": "LandShark, `landshark_diagram.yaml`", "blocks": nb, **t}
            print(f"generate LandShark: median {t['median_wall']:.2f} s", flush=True)
            for n in [int(x) for x in a.sizes.split(",") if x]:
                m = work / f"chain{n}.yaml"
                synthetic(n, m)
                runs = 3 if n <= 1000 else 1
                t = generate_times(m, runs, work / f"chain{n}", env)
                out[f"chain_{n}"] = {"label": f"chain of {n:,} Gain/Sum blocks", "blocks": n, **t}
                print(f"generate chain of {n}: median {t['median_wall']:.2f} s "
                      f"({t.get('failed') or ', '.join(f'{k} {v:.2f}' for k, v in t['phases_of_median'].items())})",
                      flush=True)
                if "failed" in t:
                    # the same under an unlimited stack: what it would take if the failure is a stack limit
                    t = generate_times(m, 1, work / f"chain{n}_unlimited", env, unlimited_stack=True)
                    out[f"chain_{n}_unlimited_stack"] = {
                        "label": f"chain of {n:,} blocks, under `ulimit -s unlimited`", "blocks": n, **t}
                    print(f"generate chain of {n}, ulimit -s unlimited: {t['median_wall']:.2f} s "
                          f"{t.get('failed', '')}", flush=True)
            res["generate"] = out
    res["load_end"] = loadavg()
    save_json("controller.json", res)
    print()
    print(section(res))
    return 0


if __name__ == "__main__":
    sys.exit(main())
