/*
 * rt_minsector.h: the median of three readings, a shared utility function
 * (a pyrosgen test fixture in the shape of Embedded Coder's
 * slprj/ert/_sharedutils/rt_*.h).
 */
#ifndef SHARE_rt_minsector
#define SHARE_rt_minsector
#include "rtwtypes.h"

extern real_T rt_minsector(real_T u0, real_T u1, real_T u2);

#endif
