/*
 * ScanGuard.c: a laser guard over a whole scan (examples/scan_guard).
 *
 * Closest is the closest obstacle in the front sector, the ranges 480 to
 * 600 (a Hokuyo UTM-30LX's 1081 ranges cover 270 degrees in 0.25 degree
 * steps: index 540 is straight ahead, the sector +/- 15 degrees), among
 * the ranges the scan holds (index below NScan) that are valid (above
 * 0.05 m, the scanner's minimum; NaN compares false and is skipped); it
 * is 100 m when the sector holds none.  Vx is 0.5 m/s while Closest is
 * beyond 1.0 m and the scan holds the whole sector (NScan > 600), else 0.
 */
#include "ScanGuard.h"

#define FIRST  480
#define LAST   600

ExtU_ScanGuard_T ScanGuard_U;
ExtY_ScanGuard_T ScanGuard_Y;

void ScanGuard_step(void)
{
  int i;
  real32_T closest = 100.0F;
  for (i = FIRST; i <= LAST; i++) {
    real32_T r = ScanGuard_U.Scan[i];
    if ((uint32_T)i < ScanGuard_U.NScan && r > 0.05F && r < closest) {
      closest = r;
    }
  }
  ScanGuard_Y.Closest = closest;
  ScanGuard_Y.Vx = (closest > 1.0F && ScanGuard_U.NScan > (uint32_T)LAST) ? 0.5 : 0.0;
}

void ScanGuard_initialize(void)
{
  ScanGuard_Y.Vx = 0.0;
  ScanGuard_Y.Closest = 100.0F;
}
