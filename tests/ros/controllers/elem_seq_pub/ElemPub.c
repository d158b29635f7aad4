/*
 * ElemPub.c: test controller, no arithmetic: the Path's length is the
 * received L, its poses' x the received V0..V2, pose 1's seq L and its
 * frame_id of length S with bytes 'a', 'b'; the JointState's length L,
 * name 0 of length S with bytes "wxyz", name 2 of length S with byte 'z'.
 */
#include "ElemPub.h"

ExtU_ElemPub_T ElemPub_U;
ExtY_ElemPub_T ElemPub_Y;

void ElemPub_step(void)
{
  ElemPub_Y.NP = ElemPub_U.L;
  ElemPub_Y.X0 = ElemPub_U.V0;
  ElemPub_Y.X1 = ElemPub_U.V1;
  ElemPub_Y.X2 = ElemPub_U.V2;
  ElemPub_Y.Q1 = ElemPub_U.L;
  ElemPub_Y.FL1 = ElemPub_U.S;
  ElemPub_Y.F10 = 97U;
  ElemPub_Y.F11 = 98U;
  ElemPub_Y.NJ = ElemPub_U.L;
  ElemPub_Y.N0L = ElemPub_U.S;
  ElemPub_Y.N0[0] = 119U;
  ElemPub_Y.N0[1] = 120U;
  ElemPub_Y.N0[2] = 121U;
  ElemPub_Y.N0[3] = 122U;
  ElemPub_Y.N2L = ElemPub_U.S;
  ElemPub_Y.N2B0 = 122U;
}

void ElemPub_initialize(void)
{
  int32_T i;
  ElemPub_Y.NP = 0U;
  ElemPub_Y.X0 = 0.0;
  ElemPub_Y.X1 = 0.0;
  ElemPub_Y.X2 = 0.0;
  ElemPub_Y.Q1 = 0U;
  ElemPub_Y.FL1 = 0U;
  ElemPub_Y.F10 = 0U;
  ElemPub_Y.F11 = 0U;
  ElemPub_Y.NJ = 0U;
  ElemPub_Y.N0L = 0U;
  for (i = 0; i < 4; i++) {
    ElemPub_Y.N0[i] = 0U;
  }
  ElemPub_Y.N2L = 0U;
  ElemPub_Y.N2B0 = 0U;
}
