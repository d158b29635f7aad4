"""bench/ros2.py's parsing and aggregation (fast, nothing timed): the
callgrind_annotate reader, the per-cycle difference of two runs, the
latency summary and the BENCHMARKS.md block rendered from a result."""

import importlib.util
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[2] / "bench"


def _load():
    """bench/ros2.py under a name of its own (``ros2`` is also tests/ros2)."""
    sys.path.insert(0, str(BENCH))
    spec = importlib.util.spec_from_file_location("bench_ros2", BENCH / "ros2.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules["bench_ros2"] = mod  # its dataclasses look their module up
    spec.loader.exec_module(mod)
    return mod


ros2 = _load()

ANNOTATE = """\
--------------------------------------------------------------------------------
Ir                 
--------------------------------------------------------------------------------
980,570 (100.0%)  PROGRAM TOTALS

--------------------------------------------------------------------------------
Ir                file:function
--------------------------------------------------------------------------------
546,004 (55.68%)  ???:ros_spinOnce [/tmp/x/gen]
 76,000 ( 7.75%)  ???:ros_rate_sleep [/tmp/x/gen]
 20,020 ( 2.04%)  ./time/../sysdeps/unix/sysv/linux/clock_gettime.c:clock_gettime@@GLIBC_2.17 [/usr/lib/libc.so.6]
     12 ( 0.00%)  ./string/a.S:memcpy [/usr/lib/libc.so.6]
      8 ( 0.00%)  ./string/b.S:memcpy [/usr/lib/libc.so.6]
  6,144 ( 0.63%)  ./elf/../sysdeps/generic/dl-new-hash.h:_dl_lookup_symbol_x
      .           ./csu/../csu/libc-start.c:__libc_start_main@@GLIBC_2.34 [/usr/lib/libc.so.6]
"""


def test_parse_annotate_reads_self_counts_and_sums_a_function_over_files():
    got = ros2.parse_annotate(ANNOTATE)
    assert got == {"ros_spinOnce": 546004, "ros_rate_sleep": 76000, "clock_gettime@@GLIBC_2.17": 20020,
                   "memcpy": 20, "_dl_lookup_symbol_x": 6144}
    assert ros2.program_total(ANNOTATE) == 980570


def test_program_total_missing_is_an_error():
    with pytest.raises(ValueError, match="PROGRAM TOTALS"):
        ros2.program_total("nothing here\n")


def test_per_cycle_is_the_difference_over_the_cycles_and_drops_fixed_costs():
    short = {"loop": 21010, "ros_spinOnce": 273004, "do_lookup_x": 22718}
    long = {"loop": 42010, "ros_spinOnce": 546004, "do_lookup_x": 22718, "late": 500}
    got = ros2.per_cycle(short, long, 1000, 2000)
    assert got["functions"] == {"ros_spinOnce": 273.0, "loop": 21.0, "late": 0.5}
    assert list(got["functions"]) == ["ros_spinOnce", "loop", "late"]
    assert got["total"] == pytest.approx(294.5)


def test_per_cycle_refuses_a_function_cheaper_in_the_longer_run():
    with pytest.raises(ValueError, match="loop: 10 instructions in 2000 cycles, 20 in 1000"):
        ros2.per_cycle({"loop": 20}, {"loop": 10}, 1000, 2000)
    with pytest.raises(ValueError, match="longer"):
        ros2.per_cycle({}, {}, 2000, 2000)


def test_without_fake_leaves_out_the_fake_layers_own_instructions():
    res = ros2.per_cycle({}, {"clock_gettime": 40000, "clock_gettime@@GLIBC_2.17": 20000, "loop": 21000}, 1000, 2000)
    got = ros2.without_fake(res)
    assert got["functions"] == {"clock_gettime@@GLIBC_2.17": 20.0, "loop": 21.0}
    assert (got["total"], got["fake_left_out"]) == (41.0, 40.0)


def test_latency_summary():
    s = ros2.latency_summary([3.0, 1.0, 2.0, 4.0], 5)
    assert (s["rounds"], s["answered"], s["median"], s["p10"], s["p90"], s["max"]) == (5, 4, 2.5, 1.0, 4.0, 4.0)
    with pytest.raises(ValueError):
        ros2.latency_summary([], 5)


def _result(gen_total, hw_total, lat_ratio):
    side = {"rounds": 10, "answered": 10, "median": 1.0, "p10": 0.9, "p90": 1.1, "p99": 1.2, "max": 2.0}
    row = {"generated": {"total": gen_total, "functions": {"ros_spinOnce": gen_total}},
           "handwritten": {"total": hw_total, "functions": {"main": hw_total}}, "ratio": gen_total / hw_total}
    return {"when": "2026-11-28 20:00 UTC", "mode": "full", "load_at_start": "1.00 1.00 1.00",
            "load_at_end": "2.00 2.00 2.00",
            "build_s": {"ros2": {"median": 3.0, "runs": [3.0]}, "ros1": {"median": 6.0, "runs": [6.0]}, "ratio": 0.5},
            "nodes": {"landshark": {"model": "m.yaml", "stamp_dropped": False, "instructions": {"mixed": row},
                                    "latency": {"generated": side, "handwritten": side,
                                                "turns": [{"generated": 1.0, "handwritten": 1.0}],
                                                "ratio_of_medians": lat_ratio}}}}


def test_report_block_says_met_or_missed_from_the_figures():
    text = ros2.report_block(_result(465, 111, 1.001))
    assert "| landshark: round-trip ratio generated / hand-written (medians, 1 ms period) | ≤ 1.05 | 1.001 | met |" \
        in text
    assert "465 / 111 = 4.19 | missed |" in text
    assert "3.00 s / 6.00 s = 0.50" in text
    assert "load 1.00 1.00 1.00 at the start and 2.00 2.00 2.00 at the end" in text
    text = ros2.report_block(_result(100, 111, 1.06))
    assert "1.060 | missed |" in text and "100 / 111 = 0.90 | met |" in text


def test_report_block_without_a_run():
    assert "No ROS 2 run recorded" in ros2.report_block(None)
    assert "No ROS 2 run recorded" in ros2.report_block({"round_trip_ms_1ms_period": {}})


def test_leftover_segments_are_the_new_unmapped_fast_dds_ones(tmp_path, monkeypatch):
    for name in ("fastdds_old", "fastdds_ours", "fastdds_ours_el", "sem.fastdds_port7_mutex", "fastdds_port7",
                 "fastdds_theirs", "other"):
        (tmp_path / name).write_text("")
    monkeypatch.setattr(ros2, "SHM", tmp_path)
    monkeypatch.setattr(ros2, "_mapped", lambda: {"fastdds_theirs", "fastdds_port7_mutex"})
    assert ros2.leftover_segments({"fastdds_old"}) == ["fastdds_ours", "fastdds_ours_el", "fastdds_port7"]


WRAPPER = """\
void ros_rate_sleep(void)
{
    long long now = steady_ns();
    g_next_ns += PYROSGEN_PERIOD_NS;
}
"""


def test_what_if_changes_apply_or_say_they_are_stale():
    got = ros2.patched(WRAPPER, list(ros2.WHAT_IF))
    assert "steady_ns" not in got
    assert "long long now = 0;\n    g_next_ns += PYROSGEN_PERIOD_NS;" in got
    with pytest.raises(ValueError, match="does not apply"):
        ros2.patched(got, list(ros2.WHAT_IF))


ANNOTATED = """\
--------------------------------------------------------------------------------
-- Auto-annotated source: /tmp/x/other.c
--------------------------------------------------------------------------------
  9 ( 1.00%)  int other(void) { return 1; }
--------------------------------------------------------------------------------
-- Auto-annotated source: /tmp/x/n_rcl.c
--------------------------------------------------------------------------------
    .           /* n_rcl.c */
    .           static inline void to_c_T(const int *r, int *c)
    .           {
1,000 ( 2.00%)      *c = *r;
    .           }
    .           \n\
    2 ( 0.00%)  void ros_spinOnce(void)
    .           {
3,000 ( 6.00%)      take();
2,000 ( 4.00%)  => /tmp/x/n_rcl.c:take (1,000x)
    .           }
--------------------------------------------------------------------------------
Ir
--------------------------------------------------------------------------------
6,002 (12.00%)  events annotated
"""
SOURCE = """\
/* n_rcl.c */
static inline void to_c_T(const int *r, int *c)
{
    *c = *r;
}

void ros_spinOnce(void)
{
    take();
}
"""


def test_source_line_counts_and_function_counts():
    counts = ros2.source_line_counts(ANNOTATED, "n_rcl.c")
    assert counts == [0, 0, 0, 1000, 0, 0, 2, 0, 3000, 0]
    assert ros2.function_spans(SOURCE) == {"to_c_T": (1, 4), "ros_spinOnce": (6, 9)}
    assert ros2.function_counts(SOURCE, counts) == {"to_c_T": 1000, "ros_spinOnce": 3002}
    with pytest.raises(ValueError, match="0 annotated sources"):
        ros2.source_line_counts(ANNOTATED, "missing_rcl.c")


FLOOR_GLUE = "".join(f"void {t}_callback(struct geometry_msgs_TwistStamped *msg);\n" for t in "abc") + \
    "".join(f"void {t}_callback(struct geometry_msgs_TwistStamped *msg)\n{{\n}}\n" for t in "abc") + \
    "".join(f"    ros_subscribe_{t}(&{t}_callback);\n" for t in "abc")
FLOOR_RCL = "".join(f"        to_c_geometry_msgs_TwistStamped(&g_take_{t}, &g_buf_{t});\n"
                    f"        g_cb_{t}(&g_buf_{t});\n" for t in "abc") + "    long long now = steady_ns();\n"


def test_floor_variants_apply_or_say_they_are_stale():
    got = ros2.floor_variants(FLOOR_GLUE, FLOOR_RCL)
    assert list(got) == ["one translation unit", "in place, one translation unit",
                         "in place, one translation unit, no late-cycle rule"]
    assert got["one translation unit"] == (FLOOR_GLUE, FLOOR_RCL)
    g, r = got["in place, one translation unit"]
    assert "void a_callback(geometry_msgs__msg__TwistStamped *msg)\n{" in g
    assert "ros_subscribe_b((void (*)(struct geometry_msgs_TwistStamped *))&b_callback);" in g
    assert "to_c_" not in r and "g_cb_c((struct geometry_msgs_TwistStamped *)(void *)&g_take_c);" in r
    assert "steady_ns" in r and "long long now = 0;" in got["in place, one translation unit, no late-cycle rule"][1]
    with pytest.raises(ValueError, match="applies 2 times, not 3"):
        ros2.floor_variants(FLOOR_GLUE, FLOOR_RCL.replace("g_take_c, &g_buf_c", "x"))
