/*
 * Rover_types.h
 *
 * Code generation for model "Rover" (a pyrosgen test fixture in the shape
 * of Embedded Coder's <model>_ert_rtw/ folder, written by hand).
 */
#ifndef RTW_HEADER_Rover_types_h_
#define RTW_HEADER_Rover_types_h_
#include "rtwtypes.h"

/* Forward declaration for rtModel */
typedef struct tag_RTM_Rover_T RT_MODEL_Rover_T;

#endif                                 /* RTW_HEADER_Rover_types_h_ */
