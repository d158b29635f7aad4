/*
 * rt_nonfinite.h: tests for IEEE non-finite values (a pyrosgen test
 * fixture in the shape of Embedded Coder's non-finite support files).
 */
#ifndef RTW_HEADER_rt_nonfinite_h_
#define RTW_HEADER_rt_nonfinite_h_
#include <stddef.h>
#include "rtwtypes.h"

extern real_T rtInf;
extern real32_T rtInfF;

extern void rt_InitInfAndNaN(size_t realSize);
extern boolean_T rtIsNaNF(real32_T value);

#endif                                 /* RTW_HEADER_rt_nonfinite_h_ */
