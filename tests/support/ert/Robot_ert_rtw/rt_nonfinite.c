/*
 * rt_nonfinite.c: tests for IEEE non-finite values (a pyrosgen test
 * fixture).
 */
#include "rt_nonfinite.h"
#include "rtGetInf.h"

real_T rtInf;
real32_T rtInfF;

/*
 * Initialize the rtInf and rtInfF.
 */
void rt_InitInfAndNaN(size_t realSize)
{
  (void) (realSize);
  rtInf = rtGetInf();
  rtInfF = rtGetInfF();
}

/* Test if single-precision value is not a number */
boolean_T rtIsNaNF(real32_T value)
{
  return (boolean_T)((value != value) ? 1U : 0U);
}
