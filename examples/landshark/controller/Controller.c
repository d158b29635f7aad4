/*
 * Controller.c: attack-resilient cruise controller for the LandShark robot.
 *
 * The velocity estimate is the median of the three sensor readings, so one
 * spoofed or failed sensor (e.g. GPS spoofing) cannot move it outside the
 * range of the two honest ones. A PI law with anti-windup drives the median
 * toward the set speed; the command is saturated to [0, VMAX].
 * Non-finite readings are treated as the worst case and rejected by the
 * median as well (a NaN is ordered as +infinity).
 */
#include "Controller.h"

ExtU_Controller_T Controller_U;
ExtY_Controller_T Controller_Y;
DW_Controller_T Controller_DW;

/* NaN-safe ordering key: NaN sorts above everything. */
static real_T Controller_key(real_T x)
{
  return (x == x) ? x : 1.0e308 * 10.0;
}

static real_T Controller_median3(real_T a, real_T b, real_T c)
{
  real_T ka = Controller_key(a), kb = Controller_key(b), kc = Controller_key(c);
  if ((ka <= kb && kb <= kc) || (kc <= kb && kb <= ka)) {
    return b;
  }
  if ((kb <= ka && ka <= kc) || (kc <= ka && ka <= kb)) {
    return a;
  }
  return c;
}

static real_T Controller_sat(real_T x, real_T lo, real_T hi)
{
  if (!(x == x)) {
    return lo;
  }
  return (x < lo) ? lo : ((x > hi) ? hi : x);
}

void Controller_step(void)
{
  real_T v_est = Controller_median3(Controller_U.In1, Controller_U.In2,
                                    Controller_U.In3);
  real_T err = Controller_SETPOINT - v_est;
  real_T integ;

  if (!(err == err)) {
    /* all three readings unusable: hold the set speed, keep the integrator */
    err = 0.0;
  }
  integ = Controller_sat(Controller_DW.Integrator_DSTATE
                         + Controller_KI * Controller_TS * err,
                         -Controller_IMAX, Controller_IMAX);
  Controller_DW.Integrator_DSTATE = integ;
  Controller_Y.Out1 = Controller_sat(Controller_SETPOINT + Controller_KP * err
                                     + integ, 0.0, Controller_VMAX);
}

void Controller_initialize(void)
{
  Controller_U.In1 = 0.0;
  Controller_U.In2 = 0.0;
  Controller_U.In3 = 0.0;
  Controller_Y.Out1 = 0.0;
  Controller_DW.Integrator_DSTATE = 0.0;
}

void Controller_terminate(void)
{
}
