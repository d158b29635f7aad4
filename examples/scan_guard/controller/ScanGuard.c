/*
 * ScanGuard.c: a laser guard over a whole scan (examples/scan_guard).
 *
 * Closest is the closest obstacle in the front sector, the ranges 480 to
 * 600 (a Hokuyo UTM-30LX's 1081 ranges cover 270 degrees in 0.25 degree
 * steps: index 540 is straight ahead, the sector +/- 15 degrees), among
 * the ranges the scan holds (index below NScan) that are valid: finite and
 * within the scanner's limits, RANGE_MIN <= r <= RANGE_MAX (a LaserScan's
 * range_min and range_max; NaN fails both comparisons, +/-Inf the second
 * or the first, 0.0 the first); it is 100 m when the sector holds none.
 * Vx is 0.5 m/s only while the scan holds the whole sector (NScan > 600),
 * the sector has at least one valid range, and Closest is beyond 1.0 m;
 * else 0: a dead sensor (a scan of NaN, of zeros, of Inf) stops the robot.
 *
 * The limits are this scanner's constants; a node for scanners whose
 * limits vary would feed the message's range_min and range_max as two
 * more controller inputs (float32 relations of the model).
 */
#include "ScanGuard.h"

#define FIRST      480
#define LAST       600
#define RANGE_MIN  0.05F   /* m: below, the scanner reports no echo */
#define RANGE_MAX  30.0F   /* m: the scanner's reach */

ExtU_ScanGuard_T ScanGuard_U;
ExtY_ScanGuard_T ScanGuard_Y;

void ScanGuard_step(void)
{
  int i;
  int valid = 0;                        /* valid ranges seen in the sector */
  real32_T closest = 100.0F;
  for (i = FIRST; i <= LAST; i++) {
    real32_T r = ScanGuard_U.Scan[i];
    if ((uint32_T)i < ScanGuard_U.NScan && r >= RANGE_MIN && r <= RANGE_MAX) {
      valid = 1;
      if (r < closest) {
        closest = r;
      }
    }
  }
  ScanGuard_Y.Closest = closest;
  ScanGuard_Y.Vx = (valid && closest > 1.0F && ScanGuard_U.NScan > (uint32_T)LAST) ? 0.5 : 0.0;
}

void ScanGuard_initialize(void)
{
  ScanGuard_Y.Vx = 0.0;
  ScanGuard_Y.Closest = 100.0F;
}
