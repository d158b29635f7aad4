/*
 * rt_minsector.c: the median of three readings (a NaN counts as the
 * largest), a shared utility function (a pyrosgen test fixture).
 */
#include "rtwtypes.h"
#include "rt_nonfinite.h"
#include "rt_minsector.h"

static real_T rt_key(real_T u)
{
  return rtIsNaN(u) ? rtInf : u;
}

real_T rt_minsector(real_T u0, real_T u1, real_T u2)
{
  real_T k0 = rt_key(u0);
  real_T k1 = rt_key(u1);
  real_T k2 = rt_key(u2);
  if (((k0 <= k1) && (k1 <= k2)) || ((k2 <= k1) && (k1 <= k0))) {
    return u1;
  }

  if (((k1 <= k0) && (k0 <= k2)) || ((k2 <= k0) && (k0 <= k1))) {
    return u0;
  }

  return u2;
}
