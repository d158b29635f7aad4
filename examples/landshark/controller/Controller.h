/*
 * Controller.h: attack-resilient cruise controller for the LandShark robot.
 *
 * Written for pyrosgen in the style of Simulink Embedded Coder output
 * (ExtU_<model>_T / ExtY_<model>_T, <model>_U / <model>_Y, <model>_initialize,
 * <model>_step). Inputs: three independent velocity estimates (left wheel
 * encoder, right wheel encoder, GPS) in m/s. Output: the commanded base
 * velocity in m/s.
 */
#ifndef RTW_HEADER_Controller_h_
#define RTW_HEADER_Controller_h_

#include "rtwtypes.h"

/* External inputs (root inport signals with default storage) */
typedef struct {
  real_T In1;                          /* '<Root>/In1': left wheel velocity */
  real_T In2;                          /* '<Root>/In2': right wheel velocity */
  real_T In3;                          /* '<Root>/In3': GPS velocity */
} ExtU_Controller_T;

/* External outputs (root outports fed by signals with default storage) */
typedef struct {
  real_T Out1;                         /* '<Root>/Out1': commanded velocity */
} ExtY_Controller_T;

/* Block states (default storage) */
typedef struct {
  real_T Integrator_DSTATE;            /* '<S1>/Integrator' */
} DW_Controller_T;

/* Tunable parameters */
#define Controller_SETPOINT   (1.0)    /* cruise speed, m/s */
#define Controller_KP         (0.8)    /* proportional gain */
#define Controller_KI         (0.5)    /* integral gain, 1/s */
#define Controller_TS         (0.02)   /* sample time, s (50 Hz) */
#define Controller_VMAX       (2.0)    /* actuator saturation, m/s */
#define Controller_IMAX       (0.5)    /* integrator anti-windup bound, m/s */

extern ExtU_Controller_T Controller_U;
extern ExtY_Controller_T Controller_Y;
extern DW_Controller_T Controller_DW;

extern void Controller_initialize(void);
extern void Controller_step(void);
extern void Controller_terminate(void);

#endif /* RTW_HEADER_Controller_h_ */
