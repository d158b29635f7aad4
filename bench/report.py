"""Rewrite the generated tables of BENCHMARKS.md and the plots in
bench/results/ from the results of the last runs (bench/results/*.json).

BENCHMARKS.md is hand-written prose with generated blocks between
``<!-- BEGIN bench:NAME -->`` and ``<!-- END bench:NAME -->``; only those
blocks are replaced (a block whose results are missing says so).
"""

from __future__ import annotations

import re
from pathlib import Path

import common
from common import REPO

DOC = REPO / "BENCHMARKS.md"

#: The targets of the issue (seconds, ratios).
T_LANDSHARK = 5.0
T_N400 = 30.0
T_GROWTH = 6.0
T_PROOFS = 300.0
T_LATENCY = 1.05
T_INSTR = 1.0


def _ok(good: bool) -> str:
    return "met" if good else "**missed**"


def _s(x, nd=2) -> str:
    if x is None:
        return "–"
    return f"{x:.{nd}f}"


def _mb(kb) -> str:
    return "–" if not kb else f"{kb / 1024:.0f}"


def block_machine(load_json) -> str:
    m = load_json("machine.json")
    if not m:
        return "_No run recorded yet: `make bench`._\n"
    rows = [
        ("date", m.get("date")), ("mode", m.get("mode")), ("CPU", m.get("cpu")), ("cores", m.get("cores")),
        ("RAM", m.get("ram")), ("OS", f"{m.get('os')} (kernel {m.get('kernel')})"),
        ("load average (1, 5, 15 min) at start / end", f"{m.get('load_at_start')} / {m.get('load_at_end', '?')}"),
        ("Coq", m.get("coq")), ("OCaml", m.get("ocaml")), ("gcc", m.get("gcc")), ("valgrind", m.get("valgrind")),
        ("Python", m.get("python")),
        ("whole benchmark", f"{m.get('bench_seconds', 0) / 60:.1f} min"),
    ]
    out = ["| | |", "|---|---|"] + [f"| {k} | {v} |" for k, v in rows]
    out.append("")
    out.append("The machine is shared (2 cores, other jobs running): every figure has the load "
               "average of its run next to it, wall times are inflated by the load, CPU times "
               "(user + system, from the kernel's accounting) much less.")
    return "\n".join(out) + "\n"


def _by(res) -> dict:
    return {m["label"]: m for m in res["models"]}


def block_pipeline_targets(load_json) -> str:
    res = load_json("pipeline.json")
    if not res:
        return "_Not run yet._\n"
    by = _by(res)
    rows = ["| figure | target | measured | |", "|---|---|---|---|"]
    ls = by.get("landshark")

    def wl(m, key):  # best run (median of the runs)
        mn = m.get(key + "_min", m[key])
        return f"{mn:.2f} s ({m[key]:.2f} s)"

    def lds(m):
        return ", ".join(x.split()[0] for x in m["loads"])

    if ls:
        rows.append(f"| LandShark, `pyrosgen generate` end to end, wall | ≤ {T_LANDSHARK:.0f} s | {wl(ls, 'cli_wall')} "
                    f"| {_ok(ls.get('cli_wall_min', ls['cli_wall']) <= T_LANDSHARK)} |")
        rows.append(f"| LandShark, same, CPU time (the wall time on an idle machine: the pipeline is sequential) "
                    f"| ≤ {T_LANDSHARK:.0f} s | {wl(ls, 'cli_cpu')} | {_ok(ls.get('cli_cpu_min', ls['cli_cpu']) <= T_LANDSHARK)} |")
    n4 = by.get("synth_400")
    if n4:
        rows.append(f"| N = 400, end to end, wall | ≤ {T_N400:.0f} s "
                    f"| {wl(n4, 'cli_wall')} | {_ok(n4.get('cli_wall_min', n4['cli_wall']) <= T_N400)} |")
    r = res.get("ratios", {})
    if "cli t(2000)/t(400)" in r:
        g = r["cli t(2000)/t(400)"]
        rows.append(f"| growth t(2000) / t(400), wall, same run | ≤ {T_GROWTH:.0f} | {g:.2f} | {_ok(g <= T_GROWTH)} |")
        gc = r["cli cpu(2000)/cpu(400)"]
        rows.append(f"| growth, CPU time | ≤ {T_GROWTH:.0f} | {gc:.2f} | {_ok(gc <= T_GROWTH)} |")
    else:
        rows.append("| growth t(2000) / t(400) | ≤ 6 | not measured (quick run) | |")
    rows.append("")
    rows.append("Best run, median of the runs in brackets (the load of other jobs only adds time, so the "
                "best run is the estimate of pyrosgen's own cost); ratios of best runs. Load average "
                "(1 min) at each run: " + "; ".join(f"{m['label']} {lds(m)}" for m in res["models"]) + ".")
    return "\n".join(rows) + "\n"


PHASES = ("front end", "coqc", "checking", "printing")


def block_pipeline_phases(load_json) -> str:
    res = load_json("pipeline.json")
    if not res:
        return "_Not run yet._\n"
    head = ("| model | N | glue lines | front end | coqc | checking | printing | validation | gcc -O2 | "
            "in-process total | CLI wall | CLI CPU | coqc peak MB | load (1 min) |")
    rows = [head, "|" + "|".join(["---"] * 14) + "|"]
    for m in res["models"]:
        ph = m["phases"]
        val = m.get("validation") or {}
        loads = sorted(float(x.split()[0]) for x in m["loads"])
        rows.append(
            f"| {m['label']} | {m['n']} | {m['glue_lines']} | "
            + " | ".join(_s(ph.get(p)) for p in PHASES)
            + f" | {_s(val.get('wall'))} | {_s(m['gcc']['wall'])} | {_s(m['inproc_total'])} | "
            f"{_s(m['cli_wall'])} | {_s(m['cli_cpu'])} | {_mb(m['tools'].get('coqc', {}).get('maxrss_kb'))} | "
            f"{loads[0]:.1f}–{loads[-1]:.1f} |")
    rows.append("")
    rows.append("Seconds (median of the runs); phases as `pyrosgen generate` reports them (its "
                "printing phase includes the printer validation when the pipeline runs it; "
                "the validation column times it again on its own); `gcc -O2` compiles the "
                "printed glue (`-c`).")
    return "\n".join(rows) + "\n"


def block_pipeline_tools(load_json) -> str:
    res = load_json("pipeline.json")
    if not res:
        return "_Not run yet._\n"
    tools = []
    for m in res["models"]:
        for t in m["tools"]:
            if t not in tools:
                tools.append(t)
    head = "| model | " + " | ".join(f"{t} wall / CPU / MB" for t in tools) + " |"
    rows = [head, "|" + "|".join(["---"] * (len(tools) + 1)) + "|"]
    for m in res["models"]:
        cells = []
        for t in tools:
            d = m["tools"].get(t)
            cells.append("–" if not d else f"{d['wall']:.2f} / {d['cpu']:.2f} / {_mb(d['maxrss_kb'])}")
        rows.append(f"| {m['label']} | " + " | ".join(cells) + " |")
    return "\n".join(rows) + "\n"


def block_pipeline_profile(load_json) -> str:
    res = load_json("pipeline.json")
    if not res:
        return "_Not run yet._\n"
    out = []
    for m in res["models"]:
        prof = m.get("coq_profile")
        if not prof:
            continue
        sizes = ""
        if m.get("v_bytes"):
            sizes = (f" (per-node .v {m['v_bytes'] / 1024:.0f} KB, .vo {m.get('vo_bytes', 0) / 1024:.0f} KB, "
                     f"extracted job.ml {m.get('job_ml_bytes', 0) / 1024:.0f} KB)")
        out.append(f"**{m['label']}**{sizes}: slowest commands of `coqc -time` on the per-node file")
        out.append("")
        out.append("| command | wall s | CPU s |")
        out.append("|---|---|---|")
        for r in prof[:6]:
            cmd = r["command"].replace("|", "\\|")
            out.append(f"| `{cmd}` | {r['wall']:.2f} | {r['cpu']:.2f} |")
        out.append("")
    return "\n".join(out) + "\n" if out else "_No profile in this run._\n"


def block_ab(load_json) -> str:
    res = load_json("pipeline.json")
    abs_ = (res or {}).get("ab")
    if not abs_:
        return "_Not measured in this run._\n"
    if isinstance(abs_, dict):  # older result format
        abs_ = [dict(abs_, label="landshark")]
    rows = ["| model, in-process pipeline | runs | before the fixes | after | gain | load (1, 5, 15 min) at start / end |",
            "|---|---|---|---|---|---|"]
    for a in abs_:
        for k, what in (("wall", "total, wall"), ("cpu", "total, CPU"), ("coqc", "coqc phase"),
                        ("printing", "printing phase")):
            if k not in a["before"]:
                continue
            b, f = a["before"][k], a["after"][k]
            rows.append(f"| {a['label']}: {what} | {a['runs']} | {b:.2f} s | {f:.2f} s | {b - f:.2f} s "
                        f"({100 * (b - f) / b:.0f} %) | {a['load'] if k == 'wall' else ''} |")
    rows.append("")
    rows.append("Medians of alternated runs (before, after, after, before, ...) in the same benchmark run.")
    return "\n".join(rows) + "\n"


def block_proofs(load_json) -> str:
    res = load_json("proofs.json")
    if not res:
        return "_Not run yet._\n"
    rows = ["| step (`coq/Makefile` target) | wall s | CPU s | peak MB | load (1, 5, 15 min) |", "|---|---|---|---|---|"]
    for s in res["steps"]:
        rows.append(f"| `{s['target']}` | {s['wall']:.1f} | {s['cpu']:.1f} | {_mb(s['maxrss_kb'])} | {s['load']} |")
    tot = res["total_wall"]
    rows.append(f"| **total `make proofs` from clean** | **{tot:.1f}** | {res['total_cpu']:.1f} | | |")
    rows.append("")
    rows.append(f"Target ≤ {T_PROOFS / 60:.0f} min: {_ok(tot <= T_PROOFS)} ({tot / 60:.1f} min, "
                f"{res.get('machine', {}).get('date', '')}).")
    if res.get("files"):
        rows.append("")
        rows.append(f"Slowest of the {res['n_files']} library files (coq_makefile `TIMED=1`):")
        rows.append("")
        rows.append("| file | wall s | peak MB |")
        rows.append("|---|---|---|")
        for f in res["files"][:6]:
            rows.append(f"| {f['file']} | {f['wall']:.1f} | {f['mem_kb'] / 1024:.0f} |")
    return "\n".join(rows) + "\n"


def _latency_tables(lat: dict) -> list[str]:
    """The latency tables of a ``runtime.latency`` result (both nodes, then
    round by round)."""
    out = []
    per = lat.get("edges_per_round", lat.get("edges_per_block"))
    out.append(f"Latency (µs) from the publication of an input change to the receipt of the first "
               f"command reflecting it, both nodes at a 1 ms period running side by side, the driver "
               f"alternating edges between them; {len(lat.get('rounds', []))} round(s) of {per} edges "
               f"per node, fresh nodes each round:")
    out.append("")
    out.append("| node | edges | median | mean | p10 | p90 | p99 | lost |")
    out.append("|---|---|---|---|---|---|---|---|")
    for k in ("generated", "handwritten"):
        s_ = lat[k]
        out.append(f"| {k} | {s_['n']} | {s_['median']:.0f} | {s_['mean']:.0f} | {s_['p10']:.0f} | "
                   f"{s_['p90']:.0f} | {s_['p99']:.0f} | {lat['lost'][k]} |")
    out.append("")
    if lat.get("rounds"):
        out.append("| round | generated median µs | hand-written median µs | ratio | load (1, 5, 15 min) |")
        out.append("|---|---|---|---|---|")
        for r in lat["rounds"]:
            out.append(f"| {r['round']} | {r['generated']['median']:.0f} | {r['handwritten']['median']:.0f} | "
                       f"{r['ratio_median']:.3f} | {r['load']} |")
        out.append("")
    return out


def block_runtime(load_json) -> str:
    res = load_json("runtime.json")
    if not res:
        return "_Not run yet._\n"
    out = []
    ins = res.get("instructions")
    lat = res.get("latency")
    out.append("| figure | target | measured | |")
    out.append("|---|---|---|---|")
    if lat:
        r = lat["ratio_median"]
        lo, hi = lat["ratio_median_ci95"]
        out.append(f"| latency ratio generated / hand-written (medians, 1 ms period) | ≤ {T_LATENCY} | "
                   f"{r:.3f} (95 % bootstrap interval {lo:.3f}–{hi:.3f}) | {_ok(r <= T_LATENCY)} |")
    if ins:
        r = ins["ratio"]
        out.append(f"| glue instructions per cycle, generated / hand-written | ≤ {T_INSTR:.0f} | "
                   f"{ins['generated']['per_cycle']:.0f} / {ins['handwritten']['per_cycle']:.0f} = {r:.2f} "
                   f"| {_ok(r <= T_INSTR)} |")
    out.append("")
    if ins:
        out.append("Instructions per cycle (callgrind, exact; fake ROS, `-O2`, no inlining between the "
                   "counted functions):")
        out.append("")
        out.append("| code | per cycle | by function |")
        out.append("|---|---|---|")
        names = {"generated": "generated glue (callbacks + input_glue + output_glue)",
                 "handwritten": "hand-written (callbacks + building and destroying the command)",
                 "generated_production_loop": "generated glue as `pyrosgen build` compiles it (-O2: "
                                              "input/output glue inlined into `loop`; includes loop control)",
                 "roscpp_roundtrip": "for scale: roscpp serialize + deserialize of one TwistStamped"}
        for k in ("generated", "handwritten", "generated_production_loop", "roscpp_roundtrip"):
            d = ins.get(k)
            if d:
                fs = ", ".join(f"`{f}` {v:.0f}" for f, v in sorted(d["functions"].items(), key=lambda kv: -kv[1]))
                out.append(f"| {names[k]} | {d['per_cycle']:.0f} | {fs} |")
        out.append("")
    wh = res.get("whole")
    if wh:
        out.append(f"Whole nodes, instructions per cycle (callgrind on the real processes, every thread, "
                   f"20 ms period, inputs published at 50 Hz, {wh['window_s']:.0f} s window after a warm-up, "
                   f"{wh.get('rounds', 1)} alternated round(s), sums over the rounds; timing-dependent "
                   f"(how many messages each spinOnce finds), so not exact like the table above):")
        out.append("")
        out.append("| node | per cycle | main-thread loop | of which `ros::spinOnce` | watchdog thread | cycles | load per round |")
        out.append("|---|---|---|---|---|---|---|")
        for k in ("generated", "handwritten"):
            d = wh[k]
            p = d["parts_per_cycle"]
            rounds = ", ".join(f"{x:.0f}" for x in d.get("per_round", []))
            out.append(f"| {k} | {d['per_cycle']:.0f} (rounds: {rounds}) | {p.get('main thread loop', 0):.0f} | "
                       f"{p.get('ros::spinOnce', 0):.0f} | {p.get('watchdog thread', 0):.0f} | {d['cycles']} | {d['load']} |")
        out.append(f"| ratio | {wh['ratio']:.3f} | | | | | |")
        out.append("")
    if lat:
        out += _latency_tables(lat)
    b = res.get("build")
    if b:
        out.append(f"`pyrosgen build` of the 1 ms node: {b['wall']:.1f} s wall, {b['cpu']:.1f} s CPU ({b['times']}).")
    return "\n".join(out) + "\n"


def _cxx(name: str) -> str:
    """A demangled C++ function name, shortened for a table."""
    for long, short in (("std::__cxx11::basic_string<char, std::char_traits<char>, std::allocator<char> >", "std::string"),
                        ("_<std::allocator<void> >", ""), ("std::vector<float, std::allocator<float> >", "std::vector<float>"),
                        ("std::vector<unsigned char, std::allocator<unsigned char> >", "std::vector<uint8_t>"),
                        ("ros::serialization::", ""), ("@@GLIBC_2.2.5", "")):
        name = name.replace(long, short)
    return re.sub(r"^void ", "", name)


_NOT_RUN = "_Not run yet: `.venv/bin/python bench/{}.py`._\n"
_FIGURES_HEAD = ("| figure | target | measured | |", "|---|---|---|---|")


def _latency_row(lat: dict, what: str) -> str:
    r = lat["ratio_median"]
    lo, hi = lat["ratio_median_ci95"]
    return (f"| {what} latency ratio generated / hand-written (medians, 1 ms period) | ≤ {T_LATENCY} | "
            f"{r:.3f} (95 % bootstrap interval {lo:.3f}–{hi:.3f}) | {_ok(r <= T_LATENCY)} |")


def _functions(funcs: dict) -> str:
    """A count's functions, most first (callgrind's names shortened)."""
    return ", ".join(f"`{_cxx(f)}` {v:.1f}" for f, v in sorted(funcs.items(), key=lambda kv: -kv[1])
                     if abs(v) >= 0.05)


def _guard_footer(res: dict, lat: dict | None) -> list[str]:
    """The latency tables, the build and the run of a laser node's block."""
    out = _latency_tables(lat) if lat else []
    b = res.get("build")
    if b:
        out.append(f"`pyrosgen build` of the 1 ms node: {b['wall']:.1f} s wall, {b['cpu']:.1f} s CPU.")
    m = res.get("machine") or {}
    if m:
        end = f", at end {m['load_at_end']}" if m.get("load_at_end") else ""
        out.append(f"Run {m.get('date')}, load average at start {m.get('load_at_start')}{end}.")
    return out


def block_laserscan(load_json) -> str:
    """BENCHMARKS.md section 10: the laser guard against a hand-written node
    (bench/laserscan.py)."""
    res = load_json("laserscan.json")
    if not res:
        return _NOT_RUN.format("laserscan")
    ins, lat = res.get("instructions"), res.get("latency")
    out = list(_FIGURES_HEAD)
    if ins:
        g, h = ins["generated"], ins["handwritten"]
        r = ins["ratio"]
        out.append(f"| LaserScan glue instructions per cycle, generated / hand-written | ≤ {T_INSTR:.0f} | "
                   f"{g['per_cycle']:.0f} / {h['per_cycle']:.0f} = {r:.2f} | {_ok(r <= T_INSTR)} |")
        if "ratio_without_time" in ins:
            r2 = ins["ratio_without_time"]
            out.append(f"| the same without reading the clock (`ros_time_sec`/`nsec`; `ros::Time::now()`) | "
                       f"≤ {T_INSTR:.0f} | {g['per_cycle'] - g['time_source']:.0f} / "
                       f"{h['per_cycle'] - h['time_source']:.0f} = {r2:.2f} | {_ok(r2 <= T_INSTR)} |")
    if lat:
        out.append(_latency_row(lat, "LaserScan"))
    out.append("")
    if ins:
        out.append("Instructions per cycle (callgrind, exact; fake ROS, one scan per cycle, scans of 0 to 2000 "
                   "ranges in turn, `-O2`, no inlining between the counted functions):")
        out.append("")
        out.append("| code | per cycle | of which the time stamp | by function |")
        out.append("|---|---|---|---|")
        names = {"generated": "generated glue (callback + input_glue + output_glue, and the ROS API's "
                              "`ros_time_sec`/`ros_time_nsec` they call)",
                 "handwritten": "hand-written (callback + building and destroying the command, "
                                "`ros::Time::now()` included, on simulated time)",
                 "roscpp_roundtrip": "for scale: roscpp serialize + deserialize of the same scans"}
        for k in ("generated", "handwritten", "roscpp_roundtrip"):
            d = ins.get(k)
            if not d:
                continue
            ts = f"{d['time_source']:.0f}" if "time_source" in d else ""
            out.append(f"| {names[k]} | {d['per_cycle']:.0f} | {ts} | {_functions(d['functions'])} |")
        out.append("")
        out.append(f"Both harnesses publish the same commands: `{ins['check']}`.")
        out.append("")
    out += _guard_footer(res, lat)
    return "\n".join(out) + "\n"


def block_scan_guard(load_json) -> str:
    """BENCHMARKS.md section 11: the scan guard against a hand-written node
    (bench/scan_guard.py)."""
    res = load_json("scan_guard.json")
    if not res:
        return _NOT_RUN.format("scan_guard")
    ins, lat = res.get("instructions"), res.get("latency")
    out = list(_FIGURES_HEAD)
    scans = {"mixed": "scans of 0 to 2,000 ranges", "full": "every scan 1,081 ranges"}
    if ins:
        for key, label in (("generated", "glue (as section 10)"),
                           ("generated_wrapper", "glue + the wrapper's per-message code")):
            for sc in ("mixed", "full"):
                c = ins[sc]["counts"]
                g, h = c[key]["per_cycle"], c["handwritten"]["per_cycle"]
                out.append(f"| scan guard {label} / hand-written, instructions per cycle, {scans[sc]} | "
                           f"≤ {T_INSTR:.0f} | {g:.0f} / {h:.0f} = {g / h:.2f} | {_ok(g / h <= T_INSTR)} |")
    if lat:
        out.append(_latency_row(lat, "scan guard"))
    out.append("")
    if ins:
        names = {"generated": "generated glue", "generated_wrapper": "generated glue + wrapper",
                 "handwritten": "hand-written"}
        out.append("Where the instructions go: each part with what it calls (callgrind inclusive counts, per "
                   "cycle; exact; fake ROS, `-O2`, the glue `-fno-inline`):")
        out.append("")
        out.append(f"| code | part | {scans['mixed']} | {scans['full']} |")
        out.append("|---|---|---:|---:|")
        for key in ("generated", "generated_wrapper", "handwritten"):
            pm, pf = ins["mixed"]["counts"][key]["parts"], ins["full"]["counts"][key]["parts"]
            for part in pm:
                out.append(f"| {names[key]} | `{part}` | {pm[part]:.1f} | {pf[part]:.1f} |"
                           if ":" not in part else f"| {names[key]} | {part} | {pm[part]:.1f} | {pf[part]:.1f} |")
            out.append(f"| {names[key]} | **per cycle** | **{ins['mixed']['counts'][key]['per_cycle']:.1f}** | "
                       f"**{ins['full']['counts'][key]['per_cycle']:.1f}** |")
        out.append("")
        out.append(f"By function (self counts per cycle, {scans['mixed']}):")
        out.append("")
        out.append("| code | per cycle | by function |")
        out.append("|---|---|---|")
        for key in ("generated", "generated_wrapper", "handwritten"):
            d = ins["mixed"]["counts"][key]
            out.append(f"| {names[key]} | {d['per_cycle']:.1f} | {_functions(d['functions'])} |")
        rt = ins.get("roscpp_roundtrip")
        if rt:
            out.append(f"| for scale: roscpp serialize + deserialize of the same scans | {rt['per_cycle']:.0f} | |")
        out.append("")
        bl = ins.get("by_length")
        if bl:
            out.append("Per cycle with every scan of one length (totals; the harnesses agree at each):")
            out.append("")
            out.append("| ranges per scan | generated glue | glue + wrapper | hand-written | glue / hand-written "
                       "| glue + wrapper / hand-written |")
            out.append("|---:|---:|---:|---:|---:|---:|")
            for n, d in bl.items():
                h = d["handwritten"]
                out.append(f"| {int(n):,} | {d['generated']:.0f} | {d['generated_wrapper']:.0f} | {h:.0f} | "
                           f"{d['generated'] / h:.2f} | {d['generated_wrapper'] / h:.2f} |")
            out.append("")
        av = ins.get("avx2")
        if av:
            out.append(f"For reference, the same glue compiled with `-mavx2` too (32-byte moves; `pyrosgen build` "
                       f"compiles for any x86-64): {av['mixed']['per_cycle']:.0f} per cycle with the mixed scans, "
                       f"{av['full']['per_cycle']:.0f} with every scan 1,081 ranges "
                       f"({_functions(av['full']['functions'])}), against "
                       f"{ins['full']['counts']['handwritten']['per_cycle']:.0f} hand-written.")
            out.append("")
        out.append(f"All three harnesses publish the same commands: `{ins['mixed']['check']}` "
                   f"(every scan 1,081 ranges: `{ins['full']['check']}`).")
        out.append("")
    out += _guard_footer(res, lat)
    return "\n".join(out) + "\n"


def plots(load_json, log) -> list[str]:
    res = load_json("pipeline.json")
    if not res:
        return []
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ms = [m for m in res["models"] if m["label"].startswith("synth_")]
    if len(ms) < 2:
        return []
    ns = [m["n"] for m in ms]
    made = []
    fig, ax = plt.subplots(figsize=(7, 5))
    for p in PHASES:
        ys = [m["phases"].get(p) for m in ms]
        if all(y is not None and y > 0 for y in ys):
            ax.plot(ns, ys, "o-", label=p)
    ax.plot(ns, [m["cli_wall"] for m in ms], "k*-", label="end to end (CLI, wall)")
    ax.plot(ns, [m["cli_cpu"] for m in ms], "k+--", label="end to end (CLI, CPU)")
    ax.plot(ns, [m["gcc"]["wall"] for m in ms], "s:", label="gcc -O2 of the glue")
    ax.axhline(T_N400, color="r", lw=0.8, ls="--")
    ax.annotate(f"target N = 400: {T_N400:.0f} s", (ns[0], T_N400 * 1.08), color="r", fontsize=8)
    # linear reference through the N = 400 end-to-end point
    if 400 in ns:
        y4 = ms[ns.index(400)]["cli_wall"]
        ax.plot([40, 2000], [y4 * 40 / 400, y4 * 2000 / 400], color="grey", lw=0.8, ls=":", label="linear (slope 1)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("N (relations)")
    ax.set_ylabel("seconds")
    load = res.get("machine", {}).get("load_at_start", "?")
    ax.set_title(f"pyrosgen generate: time per phase vs N (load {load})", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(True, which="both", lw=0.3)
    results = common.results_dir()
    results.mkdir(parents=True, exist_ok=True)
    p = results / "pipeline_phases.png"
    fig.tight_layout()
    fig.savefig(p, dpi=110)
    plt.close(fig)
    made.append(p.name)
    # tools (CPU)
    fig, ax = plt.subplots(figsize=(7, 5))
    tools = []
    for m in ms:
        for t in m["tools"]:
            if t not in tools:
                tools.append(t)
    for t in tools:
        ys = [m["tools"].get(t, {}).get("cpu") for m in ms]
        if all(y is not None and y > 0 for y in ys):
            ax.plot(ns, ys, "o-", label=f"{t} (CPU)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("N (relations)")
    ax.set_ylabel("CPU seconds")
    ax.set_title("pyrosgen generate: CPU time of each tool vs N", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(True, which="both", lw=0.3)
    p = results / "pipeline_tools.png"
    fig.tight_layout()
    fig.savefig(p, dpi=110)
    plt.close(fig)
    made.append(p.name)
    log(f"report: plots {', '.join(made)} in {results}")
    return made


def block_ros2(load_json) -> str:
    """BENCHMARKS.md section 13: ROS 2 against hand-written rcl nodes
    (bench/ros2.py, which renders the block)."""
    import ros2

    return ros2.report_block(load_json("ros2.json"))


BLOCKS = {
    "machine": block_machine,
    "pipeline-targets": block_pipeline_targets,
    "pipeline-phases": block_pipeline_phases,
    "pipeline-tools": block_pipeline_tools,
    "pipeline-profile": block_pipeline_profile,
    "pipeline-ab": block_ab,
    "proofs": block_proofs,
    "runtime": block_runtime,
    "laserscan": block_laserscan,
    "scan_guard": block_scan_guard,
    "ros2": block_ros2,
}


def write_blocks(load_json, names, log, doc: Path = DOC) -> None:
    """Rewrite only the blocks ``names`` of ``doc`` (a benchmark run on its
    own, e.g. bench/laserscan.py); no plots."""
    text = doc.read_text()
    for name in names:
        body = BLOCKS[name](load_json)
        pat = re.compile(rf"(<!-- BEGIN bench:{re.escape(name)} -->\n)(.*?)(<!-- END bench:{re.escape(name)} -->)", re.S)
        if not pat.search(text):
            raise RuntimeError(f"{doc} has no block {name}")
        text = pat.sub(lambda m: m.group(1) + body + m.group(3), text)
    doc.write_text(text)
    log(f"report: blocks {', '.join(names)} of {doc} rewritten")


def write_report(load_json, log, doc: Path = DOC) -> None:
    """Rewrite the blocks of ``doc`` (BENCHMARKS.md, or a copy of it for
    --quick runs) and draw the plots."""
    plots(load_json, log)
    text = doc.read_text() if doc.exists() else DOC.read_text()
    for name, fn in BLOCKS.items():
        body = fn(load_json)
        pat = re.compile(rf"(<!-- BEGIN bench:{re.escape(name)} -->\n)(.*?)(<!-- END bench:{re.escape(name)} -->)", re.S)
        if pat.search(text):
            text = pat.sub(lambda m: m.group(1) + body + m.group(3), text)
        else:
            log(f"report: BENCHMARKS.md has no block {name}: appended")
            text += f"\n<!-- BEGIN bench:{name} -->\n{body}<!-- END bench:{name} -->\n"
    doc.write_text(text)
    log(f"report: {doc} rewritten")


if __name__ == "__main__":
    import sys

    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from common import load_json

    write_report(load_json, log=print)
