/*
 * Rover.c
 *
 * Code generation for model "Rover" (a pyrosgen test fixture in the shape
 * of Embedded Coder's <model>_ert_rtw/ folder, written by hand).
 */
#include "Rover.h"
#include "Rover_private.h"

/* Block states (default storage) */
DW_Rover_T Rover_DW;

/* External inputs (root inport signals with default storage) */
ExtU_Rover_T Rover_U;

/* External outputs (root outports fed by signals with default storage) */
ExtY_Rover_T Rover_Y;

/* Real-time model */
static RT_MODEL_Rover_T Rover_M_;
RT_MODEL_Rover_T *const Rover_M = &Rover_M_;

/* Model step function */
void Rover_step(void)
{
  real_T rtb_Sum;
  real_T rtb_Integrator;
  real_T rtb_Command;

  /* Sum: '<Root>/Sum' incorporates:
   *  Constant: '<Root>/Setpoint'
   *  MATLAB Function: '<Root>/Median'
   */
  rtb_Sum = Rover_SETPOINT - rt_minsector(Rover_U.In1, Rover_U.In2, Rover_U.In3);
  if (rtIsNaN(rtb_Sum)) {
    rtb_Sum = 0.0;
  }

  /* DiscreteIntegrator: '<Root>/Integrator' */
  rtb_Integrator = Rover_DW.Integrator_DSTATE + Rover_KI_TS * rtb_Sum;
  if (rtb_Integrator > Rover_IMAX) {
    rtb_Integrator = Rover_IMAX;
  } else if (rtb_Integrator < -Rover_IMAX) {
    rtb_Integrator = -Rover_IMAX;
  }

  Rover_DW.Integrator_DSTATE = rtb_Integrator;

  /* ModelReference: '<Root>/Model' */
  rtb_Command = Rover_SETPOINT + Rover_KP * rtb_Sum + rtb_Integrator;
  Wheel(&rtb_Command, &Rover_Y.Out1);
}

/* Model initialize function */
void Rover_initialize(void)
{
  /* Registration code */

  /* initialize non-finites */
  rt_InitInfAndNaN(sizeof(real_T));

  /* Model Initialize function for ModelReference Block: '<Root>/Model' */
  Wheel_initialize();
  Rover_DW.Integrator_DSTATE = 0.0;
}

/* Model terminate function */
void Rover_terminate(void)
{
  /* (no terminate code required) */
}
