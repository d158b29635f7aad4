"""The cost of the seam's checks (BENCHMARKS.md section 4).

usage: seam.py [--baseline REV] [--rounds N]

Measures, in one run, ``pyrosgen generate`` on LandShark with this
checkout and with a baseline revision from before the seam's checks
(default 5eebb79: no model text, no certificate from proved data), the
two alternating round by round so that the machine's load falls on both
alike; the baseline is checked out into build/bench/baseline-<rev>
(``git worktree``) and its Coq library built there once.  Then, in
process, the new steps on their own: Coq's model text compared with the
front end's, the library's identity (hash of its sources), the tool
versions, and the certificate (parse the model text, locate the C lines,
hash the files, write three files).  Prints a Markdown table and saves
bench/results/seam.json.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from common import PY, REPO, WORK, loadavg, run, save_json  # noqa: E402

LANDSHARK = REPO / "examples" / "landshark" / "landshark_controller.yaml"


def baseline_tree(rev: str) -> Path:
    tree = WORK / f"baseline-{rev}"
    if not (tree / ".git").exists():
        WORK.mkdir(parents=True, exist_ok=True)
        subprocess.run(["git", "-C", str(REPO), "worktree", "add", "-f", "--detach", str(tree), rev],
                       check=True, capture_output=True)
    if not (tree / "coq" / "theories" / "Main.vo").exists() and not any((tree / "coq" / "theories").rglob("Loopproof.vo")):
        print(f"seam: building the baseline's Coq library in {tree}/coq (about 1 min)", flush=True)
        subprocess.run(["make", "-C", str(tree / "coq")], check=True, capture_output=True)
    return tree


def _site_dirs() -> list[str]:
    out = subprocess.run([str(PY), "-c", "import site; print(chr(10).join(site.getsitepackages()))"],
                         capture_output=True, text=True, check=True).stdout.split()
    return out + ["/usr/lib/python3/dist-packages"]


def generate_cmd(tree: Path, out: Path) -> tuple[list[str], dict]:
    """``python -S -m pyrosgen generate`` with ``tree`` first on the path:
    ``-S`` skips the venv's editable-install hook (which would load this
    checkout's pyrosgen); the venv's packages come through PYTHONPATH."""
    env = {"PYTHONPATH": ":".join([str(tree), *_site_dirs()]), "PATH": "/usr/bin:/bin",
           "HOME": str(Path.home()), "LC_ALL": "C.UTF-8"}
    return [str(PY), "-S", "-m", "pyrosgen", "generate", str(LANDSHARK), "-o", str(out), "-q"], env


def in_process_steps(reps: int = 20) -> dict[str, float]:
    """Median seconds of each new step, on a LandShark output folder."""
    from pyrosgen.frontend.validate import load_model
    from pyrosgen.generate import generate
    from pyrosgen.proof.coqdriver import CoqDriver
    from pyrosgen.proof.modeltext import compare_model_texts, model_text
    from pyrosgen.verify.certificate import tool_versions, write_certificate

    out = Path(tempfile.mkdtemp(prefix="seam-", dir=WORK)) / "out"
    res = generate(LANDSHARK, out)
    model = load_model(LANDSHARK)
    proved = (out / f"{model.name}.model").read_text()
    drv = CoqDriver()
    steps = {
        "model text + comparison": lambda: compare_model_texts(model_text(model), proved, vfile="x.v"),
        "library identity": drv.library_digest,
        "tool versions": tool_versions,
        "certificate (render, hash, write)": lambda: write_certificate(res.record, out, res.covered),
    }
    times = {}
    for name, fn in steps.items():
        samples = []
        for _ in range(reps if name != "tool versions" else 5):
            t0 = time.perf_counter()
            fn()
            samples.append(time.perf_counter() - t0)
        times[name] = statistics.median(samples)
    return times


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", default="5eebb79")
    ap.add_argument("--rounds", type=int, default=7)
    args = ap.parse_args()
    base = baseline_tree(args.baseline)
    for tree in (base, REPO):  # each command runs its own tree's pyrosgen
        _, env = generate_cmd(tree, WORK)
        where = subprocess.run([str(PY), "-S", "-c", "import pyrosgen; print(pyrosgen.__file__)"], env=env,
                               capture_output=True, text=True, check=True, cwd=WORK).stdout.strip()
        assert where.startswith(str(tree)), (tree, where)
    rows: dict[str, list[tuple[float, float]]] = {"baseline": [], "now": []}
    loads = []
    for i in range(args.rounds):
        for label, tree in (("baseline", base), ("now", REPO)) if i % 2 == 0 else (("now", REPO), ("baseline", base)):
            with tempfile.TemporaryDirectory(dir=WORK) as d:
                argv, env = generate_cmd(tree, Path(d) / "out")
                p = run(argv, env=env, cwd=WORK)  # not the checkout: -m puts the cwd first on the path
                rows[label].append((p.wall, p.cpu))
        loads.append(loadavg().split()[0])
        print(f"seam: round {i + 1}/{args.rounds}: baseline {rows['baseline'][-1][0]:.2f} s, "
              f"now {rows['now'][-1][0]:.2f} s (load {loads[-1]})", flush=True)
    steps = in_process_steps()
    med = {k: (statistics.median(w for w, _ in v), statistics.median(c for _, c in v), min(w for w, _ in v))
           for k, v in rows.items()}
    save_json("seam.json", {"baseline": args.baseline, "rounds": rows, "steps": steps, "loads": loads})
    print()
    print("| LandShark, `pyrosgen generate` | wall, median | CPU, median | wall, best |")
    print("|---|---|---|---|")
    for k, label in (("baseline", f"before the seam's checks ({args.baseline})"), ("now", "now")):
        w, c, b = med[k]
        print(f"| {label} | {w:.2f} s | {c:.2f} s | {b:.2f} s |")
    print(f"| ratio now / before | {med['now'][0] / med['baseline'][0]:.3f} | "
          f"{med['now'][1] / med['baseline'][1]:.3f} | {med['now'][2] / med['baseline'][2]:.3f} |")
    print()
    print("| new step (in process, median) | ms |")
    print("|---|---|")
    for k, v in steps.items():
        print(f"| {k} | {v * 1000:.1f} |")
    print(f"\n{args.rounds} alternating rounds; load average (1 min) after each: {', '.join(loads)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
