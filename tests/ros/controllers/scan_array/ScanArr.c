/*
 * ScanArr.c: test controller: Echo is Scan, element by element, and its
 * length NEcho the received one (NScan); Pt[0] is the minimum of the
 * first min(NScan, 8) elements of Scan (the received ranges; -1 when
 * there are none), Pt[1] and Pt[2] are Last[0] and Last[1].
 */
#include "ScanArr.h"

ExtU_ScanArr_T ScanArr_U;
ExtY_ScanArr_T ScanArr_Y;

void ScanArr_step(void)
{
  int i;
  int n = ScanArr_U.NScan < 8U ? (int)ScanArr_U.NScan : 8;
  real32_T m = -1.0F;
  for (i = 0; i < 8; i++) {
    ScanArr_Y.Echo[i] = ScanArr_U.Scan[i];
  }
  ScanArr_Y.NEcho = ScanArr_U.NScan;
  for (i = 0; i < n; i++) {
    if (i == 0 || ScanArr_U.Scan[i] < m) {
      m = ScanArr_U.Scan[i];
    }
  }
  ScanArr_Y.Pt[0] = m;
  ScanArr_Y.Pt[1] = ScanArr_U.Last[0];
  ScanArr_Y.Pt[2] = ScanArr_U.Last[1];
}

void ScanArr_initialize(void)
{
  int i;
  for (i = 0; i < 8; i++) {
    ScanArr_Y.Echo[i] = 0.0F;
  }
  ScanArr_Y.NEcho = 0U;
  ScanArr_Y.Pt[0] = 0.0F;
  ScanArr_Y.Pt[1] = 0.0F;
  ScanArr_Y.Pt[2] = 0.0F;
}
