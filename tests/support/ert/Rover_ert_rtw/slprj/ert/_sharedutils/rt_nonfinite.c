/*
 * rt_nonfinite.c: tests for IEEE non-finite values (a pyrosgen test
 * fixture in the shape of Embedded Coder's shared utilities).
 */
#include "rt_nonfinite.h"

real_T rtInf;
real_T rtMinusInf;

/*
 * Initialize the rtInf and rtMinusInf.
 */
void rt_InitInfAndNaN(size_t realSize)
{
  (void) (realSize);
  rtInf = 1.0e308 * 10.0;
  rtMinusInf = -rtInf;
}

/* Test if value is infinite */
boolean_T rtIsInf(real_T value)
{
  return (boolean_T)((value==rtInf || value==rtMinusInf) ? 1U : 0U);
}

/* Test if value is not a number */
boolean_T rtIsNaN(real_T value)
{
  return (boolean_T)((value!=value) ? 1U : 0U);
}
