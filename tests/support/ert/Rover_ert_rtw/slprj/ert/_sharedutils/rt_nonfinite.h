/*
 * rt_nonfinite.h: tests for IEEE non-finite values (a pyrosgen test
 * fixture in the shape of Embedded Coder's shared utilities).
 */
#ifndef RTW_HEADER_rt_nonfinite_h_
#define RTW_HEADER_rt_nonfinite_h_
#include <stddef.h>
#include "rtwtypes.h"

extern real_T rtInf;
extern real_T rtMinusInf;

extern void rt_InitInfAndNaN(size_t realSize);
extern boolean_T rtIsInf(real_T value);
extern boolean_T rtIsNaN(real_T value);

#endif                                 /* RTW_HEADER_rt_nonfinite_h_ */
