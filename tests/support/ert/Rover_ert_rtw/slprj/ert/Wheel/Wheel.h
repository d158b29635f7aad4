/*
 * Wheel.h
 *
 * Code generation for model "Wheel" (a referenced model: a saturation of
 * the commanded velocity; a pyrosgen test fixture).
 */
#ifndef RTW_HEADER_Wheel_h_
#define RTW_HEADER_Wheel_h_
#ifndef Wheel_COMMON_INCLUDES_
#define Wheel_COMMON_INCLUDES_
#include "rtwtypes.h"
#endif                                 /* Wheel_COMMON_INCLUDES_ */

#include "Wheel_types.h"

extern void Wheel_initialize(void);
extern void Wheel(const real_T *rtu_In1, real_T *rty_Out1);

#endif                                 /* RTW_HEADER_Wheel_h_ */
