"""The controller of examples/scan_guard (controller/ScanGuard.c), compiled
with gcc and run on scans: it drives only on a scan whose front sector
holds a valid range (finite, within the scanner's range_min..range_max)
and none within 1 m; a dead sensor (a scan of NaN, of zeros, of Inf,
issue 30) stops it.  The ROS node around it is tested on a real master in
tests/ros/test_scan_guard_node.py."""

from __future__ import annotations

import math
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
CTL = ROOT / "examples" / "scan_guard" / "controller"
N = 1081
NAN, INF = math.nan, math.inf

_HARNESS = r"""
#include <stdio.h>
#include <stdlib.h>
#include "ScanGuard.h"
/* argv: NScan, then "index=value" pairs over a scan of FILL (argv[2]) */
int main(int argc, char **argv)
{
  int k;
  float fill = strtof(argv[2], NULL);
  ScanGuard_initialize();
  for (k = 0; k < 1081; k++) ScanGuard_U.Scan[k] = fill;
  ScanGuard_U.NScan = (uint32_T)strtoul(argv[1], NULL, 10);
  for (k = 3; k < argc; k++) {
    int i; char v[64];
    if (sscanf(argv[k], "%d=%63s", &i, v) != 2) return 2;
    ScanGuard_U.Scan[i] = strtof(v, NULL);
  }
  ScanGuard_step();
  printf("%.17g %.9g\n", ScanGuard_Y.Vx, (double)ScanGuard_Y.Closest);
  return 0;
}
"""


@pytest.fixture(scope="module")
def guard(tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("scan_guard")
    (d / "harness.c").write_text(_HARNESS)
    exe = d / "guard"
    assert shutil.which("gcc"), "gcc is needed (make deps)"
    subprocess.run(["gcc", "-std=c11", "-Wall", "-Wextra", "-Werror", "-O2", "-I", str(CTL), str(d / "harness.c"),
                    str(CTL / "ScanGuard.c"), "-o", str(exe)], check=True, capture_output=True, text=True)
    return exe


def _run(exe: Path, nscan: int, fill: float, **at: float) -> tuple[float, float]:
    args = [str(nscan), repr(fill)] + [f"{k[1:]}={v!r}" for k, v in at.items()]
    out = subprocess.run([str(exe), *args], check=True, capture_output=True, text=True, timeout=30).stdout
    vx, closest = out.split()
    return float(vx), float(closest)


@pytest.mark.parametrize("what, nscan, fill, at, want", [
    # a dead sensor: the sector (480..600) holds no valid range -> stop
    ("all NaN", N, NAN, {}, (0.0, 100.0)),
    ("all zero", N, 0.0, {}, (0.0, 100.0)),
    ("all +Inf", N, INF, {}, (0.0, 100.0)),
    ("all -Inf", N, -INF, {}, (0.0, 100.0)),
    ("all beyond range_max", N, 40.0, {}, (0.0, 100.0)),
    ("all below range_min", N, 0.03, {}, (0.0, 100.0)),
    ("valid beside the sector only", N, NAN, {"i479": 2.0, "i601": 2.0}, (0.0, 100.0)),
    # a live sensor
    ("clear", N, 2.0, {}, (0.5, 2.0)),
    ("one valid range in a sector of NaN", N, NAN, {"i540": 2.0}, (0.5, 2.0)),
    ("an obstacle ahead", N, 2.0, {"i540": 0.5}, (0.0, 0.5)),
    ("a range below range_min is skipped", N, 2.0, {"i540": 0.03}, (0.5, 2.0)),
    ("range_min itself is valid", N, 2.0, {"i540": 0.05}, (0.0, 0.05)),
    ("range_max itself is valid", N, 30.0, {}, (0.5, 30.0)),
    ("the sector cut short", 600, 2.0, {}, (0.0, 2.0)),
    ("no range", 0, 2.0, {}, (0.0, 100.0)),
])
def test_scan_guard_stops_without_a_valid_range(guard, what, nscan, fill, at, want):
    vx, closest = _run(guard, nscan, fill, **at)
    assert (vx, closest) == pytest.approx(want), what
