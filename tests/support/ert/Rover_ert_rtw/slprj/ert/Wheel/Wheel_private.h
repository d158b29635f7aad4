/*
 * Wheel_private.h
 *
 * Code generation for model "Wheel" (a pyrosgen test fixture).
 */
#ifndef RTW_HEADER_Wheel_private_h_
#define RTW_HEADER_Wheel_private_h_
#include "rtwtypes.h"
#include "Wheel_types.h"

#define Wheel_VMAX                     (2.0)  /* upper saturation limit, m/s */
#endif                                 /* RTW_HEADER_Wheel_private_h_ */
