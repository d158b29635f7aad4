/*
 * Fusion.c: sensor fusion and safety controller for examples/multi.
 *
 * The yaw rate is the variance-weighted mean of the odometry's and the
 * gyro's, low-pass filtered. The robot drives forward at a speed
 * proportional to the free range ahead (saturated to [0, VMAX]) and damps
 * its yaw rate; it stops when the emergency stop is engaged or the range
 * is below the stop distance of the sensor type. Non-finite readings stop
 * the robot.
 */
#include "Fusion.h"

ExtU_Fusion_T Fusion_U;
ExtY_Fusion_T Fusion_Y;
DW_Fusion_T Fusion_DW;

static boolean_T Fusion_finite(real_T x)
{
  return (boolean_T)((x == x) && (x - x == 0.0));
}

static real_T Fusion_sat(real_T x, real_T lo, real_T hi)
{
  return (x < lo) ? lo : ((x > hi) ? hi : x);
}

void Fusion_step(void)
{
  real_T var_odom = Fusion_U.YawVar;
  real_T rate;
  real_T range = (real_T)Fusion_U.FrontRange;
  real_T stop_dist = (Fusion_U.RangeType == 1U) ? Fusion_STOP_IR : Fusion_STOP_US;
  boolean_T stopped;
  real_T v;

  /* variance-weighted fusion; an unusable odometry variance trusts the gyro */
  if (Fusion_finite(var_odom) && var_odom >= 0.0) {
    rate = (Fusion_GYRO_VAR * Fusion_U.YawRate + var_odom * Fusion_U.GyroZ)
      / (Fusion_GYRO_VAR + var_odom);
  } else {
    rate = Fusion_U.GyroZ;
  }
  if (Fusion_finite(rate)) {
    Fusion_DW.FusedRate_DSTATE += Fusion_ALPHA * (rate - Fusion_DW.FusedRate_DSTATE);
  }

  stopped = (boolean_T)(Fusion_U.EStop != 0U || !Fusion_finite(range) || range < stop_dist);
  v = stopped ? 0.0 : Fusion_sat(Fusion_KRANGE * (range - stop_dist), 0.0, Fusion_VMAX);

  Fusion_Y.CmdV = v;
  Fusion_Y.CmdW = stopped ? 0.0 : -Fusion_KW * Fusion_DW.FusedRate_DSTATE;
  Fusion_Y.Stopped = stopped;
  Fusion_Y.SeqOut = Fusion_U.OdomSeq;
  Fusion_Y.YawVarOut = var_odom;
  Fusion_Y.WheelCmd = (real32_T)(v / Fusion_WHEEL_RADIUS);
  Fusion_Y.Debug = Fusion_DW.FusedRate_DSTATE;
}

void Fusion_initialize(void)
{
  Fusion_DW.FusedRate_DSTATE = 0.0;
}

void Fusion_terminate(void)
{
}
