/*
 * Robot.c
 *
 * Code generation for model "Robot" (a pyrosgen test fixture in the shape
 * of Embedded Coder's <model>_ert_rtw/ folder, written by hand).
 */
#include "Robot.h"
#include "Robot_private.h"

/* External inputs (root inport signals with default storage) */
ExtU_Robot_T Robot_U;

/* External outputs (root outports fed by signals with default storage) */
ExtY_Robot_T Robot_Y;

/* Real-time model */
static RT_MODEL_Robot_T Robot_M_;
RT_MODEL_Robot_T *const Robot_M = &Robot_M_;

/* Model step function */
void Robot_step(void)
{
  int32_T i;
  boolean_T rtb_Clear;

  /* RelationalOperator: '<Root>/Compare' incorporates:
   *  Inport: '<Root>/Sectors'
   */
  rtb_Clear = Robot_U.Enable;
  for (i = 0; i < 4; i++) {
    if (rtIsNaNF(Robot_U.Sectors[i]) || (Robot_U.Sectors[i] < Robot_P.SafeDistance)) {
      rtb_Clear = false;
    }
  }

  /* Switch: '<Root>/Switch' */
  if (rtb_Clear) {
    Robot_Y.Speed = Robot_P.Cruise;
    Robot_Y.Mode = 1U;
  } else {
    Robot_Y.Speed = 0.0;
    Robot_Y.Mode = 0U;
  }

  /* End of Switch: '<Root>/Switch' */
}

/* Model initialize function */
void Robot_initialize(void)
{
  /* Registration code */

  /* initialize non-finites */
  rt_InitInfAndNaN(sizeof(real_T));
  Robot_Y.Speed = 0.0;
  Robot_Y.Mode = 0U;
}

/* Model terminate function */
void Robot_terminate(void)
{
  /* (no terminate code required) */
}
