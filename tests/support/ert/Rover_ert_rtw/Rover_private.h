/*
 * Rover_private.h
 *
 * Code generation for model "Rover" (a pyrosgen test fixture).
 */
#ifndef RTW_HEADER_Rover_private_h_
#define RTW_HEADER_Rover_private_h_
#include "rtwtypes.h"
#include "Rover_types.h"

#define Rover_SETPOINT                 (1.0)  /* cruise speed, m/s */
#define Rover_KP                       (0.8)  /* proportional gain */
#define Rover_KI_TS                    (0.01) /* integral gain times the step, 0.5 1/s * 0.02 s */
#define Rover_IMAX                     (0.5)  /* integrator bound, m/s */
#endif                                 /* RTW_HEADER_Rover_private_h_ */
