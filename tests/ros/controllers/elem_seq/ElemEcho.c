/*
 * ElemEcho.c: test controller, no arithmetic: Out holds every input in
 * input order, each converted exactly to double (Out[0] = NP, Out[1] = TP,
 * Out[2] = P0X, Out[3] = P2W, Out[4] = P1S, Out[5] = P1F0, Out[6] = P1FL,
 * Out[7] = P1FT, Out[8..11] = F2[0..3], Out[12] = NJ, Out[13] = TJ,
 * Out[14] = N0L, Out[15] = N0T, Out[16] = N2B3, Out[17..20] = N1[0..3]),
 * and NOut = 21.
 */
#include "ElemEcho.h"

ExtU_ElemEcho_T ElemEcho_U;
ExtY_ElemEcho_T ElemEcho_Y;

void ElemEcho_step(void)
{
  int32_T i;
  ElemEcho_Y.NOut = 21U;
  ElemEcho_Y.Out[0] = (real_T)ElemEcho_U.NP;
  ElemEcho_Y.Out[1] = (real_T)ElemEcho_U.TP;
  ElemEcho_Y.Out[2] = ElemEcho_U.P0X;
  ElemEcho_Y.Out[3] = ElemEcho_U.P2W;
  ElemEcho_Y.Out[4] = (real_T)ElemEcho_U.P1S;
  ElemEcho_Y.Out[5] = (real_T)ElemEcho_U.P1F0;
  ElemEcho_Y.Out[6] = (real_T)ElemEcho_U.P1FL;
  ElemEcho_Y.Out[7] = (real_T)ElemEcho_U.P1FT;
  for (i = 0; i < 4; i++) {
    ElemEcho_Y.Out[8 + i] = (real_T)ElemEcho_U.F2[i];
  }
  ElemEcho_Y.Out[12] = (real_T)ElemEcho_U.NJ;
  ElemEcho_Y.Out[13] = (real_T)ElemEcho_U.TJ;
  ElemEcho_Y.Out[14] = (real_T)ElemEcho_U.N0L;
  ElemEcho_Y.Out[15] = (real_T)ElemEcho_U.N0T;
  ElemEcho_Y.Out[16] = (real_T)ElemEcho_U.N2B3;
  for (i = 0; i < 4; i++) {
    ElemEcho_Y.Out[17 + i] = (real_T)ElemEcho_U.N1[i];
  }
}

void ElemEcho_initialize(void)
{
  int32_T i;
  ElemEcho_Y.NOut = 0U;
  for (i = 0; i < 21; i++) {
    ElemEcho_Y.Out[i] = 0.0;
  }
}
