/*
 * Robot_private.h
 *
 * Code generation for model "Robot" (a pyrosgen test fixture).
 */
#ifndef RTW_HEADER_Robot_private_h_
#define RTW_HEADER_Robot_private_h_
#include "rtwtypes.h"
#include "Robot_types.h"
#endif                                 /* RTW_HEADER_Robot_private_h_ */
