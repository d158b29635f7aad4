/*
 * rtGetInf.h: the IEEE infinities (a pyrosgen test fixture in the shape
 * of Embedded Coder's non-finite support files).
 */
#ifndef RTW_HEADER_rtGetInf_h_
#define RTW_HEADER_rtGetInf_h_
#include <stddef.h>
#include "rtwtypes.h"
#include "rt_nonfinite.h"

extern real_T rtGetInf(void);
extern real32_T rtGetInfF(void);

#endif                                 /* RTW_HEADER_rtGetInf_h_ */
