/*
 * Wheel_types.h
 *
 * Code generation for model "Wheel" (a referenced model; a pyrosgen test
 * fixture in the shape of Embedded Coder's slprj/ert/<model>/).
 */
#ifndef RTW_HEADER_Wheel_types_h_
#define RTW_HEADER_Wheel_types_h_
#include "rtwtypes.h"
#endif                                 /* RTW_HEADER_Wheel_types_h_ */
