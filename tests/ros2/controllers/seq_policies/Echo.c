/*
 * Echo.c: test controller, no arithmetic: each output of Echo_Y is the input
 * of Echo_U of the model's relations (X0 = R0, ..., PN = PL), so that what the
 * node publishes is what the glue handed the controller, bit for bit.
 */
#include "Echo.h"

ExtU_Echo_T Echo_U;
ExtY_Echo_T Echo_Y;

void Echo_step(void)
{
  Echo_Y.X0 = Echo_U.R0;
  Echo_Y.X1 = Echo_U.R1;
  Echo_Y.X2 = Echo_U.R2;
  Echo_Y.X3 = Echo_U.R3;
  Echo_Y.XN = Echo_U.RN;
  Echo_Y.XT = Echo_U.RT;
  Echo_Y.C0 = Echo_U.B0;
  Echo_Y.C1 = Echo_U.B1;
  Echo_Y.C2 = Echo_U.B2;
  Echo_Y.C3 = Echo_U.B3;
  Echo_Y.C4 = Echo_U.B4;
  Echo_Y.C5 = Echo_U.B5;
  Echo_Y.C6 = Echo_U.B6;
  Echo_Y.C7 = Echo_U.B7;
  Echo_Y.CN = Echo_U.BN;
  Echo_Y.CT = Echo_U.BT;
  Echo_Y.Q0 = Echo_U.J0;
  Echo_Y.Q1 = Echo_U.J1;
  Echo_Y.Q2 = Echo_U.J2;
  Echo_Y.Q3 = Echo_U.J3;
  Echo_Y.QN = Echo_U.JN;
  Echo_Y.T0 = Echo_U.S0;
  Echo_Y.T7 = Echo_U.S7;
  Echo_Y.TN = Echo_U.SN;
  Echo_Y.PN = Echo_U.PL;
}

void Echo_initialize(void)
{
}
