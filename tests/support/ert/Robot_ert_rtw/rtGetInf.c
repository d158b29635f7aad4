/*
 * rtGetInf.c: the IEEE infinities (a pyrosgen test fixture).
 */
#include "rtGetInf.h"

/* Return rtInf needed by the generated code. */
real_T rtGetInf(void)
{
  return 1.0e308 * 10.0;
}

/* Return rtInfF needed by the generated code. */
real32_T rtGetInfF(void)
{
  return (real32_T)(1.0e308 * 10.0);
}
