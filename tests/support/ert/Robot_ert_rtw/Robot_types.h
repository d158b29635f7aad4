/*
 * Robot_types.h
 *
 * Code generation for model "Robot" (a pyrosgen test fixture in the shape
 * of Embedded Coder's <model>_ert_rtw/ folder, written by hand).
 */
#ifndef RTW_HEADER_Robot_types_h_
#define RTW_HEADER_Robot_types_h_
#include "rtwtypes.h"

/* Parameters (default storage) */
typedef struct P_Robot_T_ P_Robot_T;

/* Forward declaration for rtModel */
typedef struct tag_RTM_Robot_T RT_MODEL_Robot_T;

#endif                                 /* RTW_HEADER_Robot_types_h_ */
