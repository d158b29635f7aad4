/*
 * Wheel.c
 *
 * Code generation for model "Wheel" (a referenced model: a saturation of
 * the commanded velocity to [0, 2] m/s; a pyrosgen test fixture).
 */
#include "Wheel.h"
#include "Wheel_private.h"
#include "rt_nonfinite.h"

/* Output and update for referenced model: 'Wheel' */
void Wheel(const real_T *rtu_In1, real_T *rty_Out1)
{
  /* Saturate: '<Root>/Saturation' */
  if (rtIsNaN(*rtu_In1) || (*rtu_In1 < 0.0)) {
    *rty_Out1 = 0.0;
  } else if (*rtu_In1 > Wheel_VMAX) {
    *rty_Out1 = Wheel_VMAX;
  } else {
    *rty_Out1 = *rtu_In1;
  }

  /* End of Saturate: '<Root>/Saturation' */
}

/* Model initialize function */
void Wheel_initialize(void)
{
  /* (no states) */
}
