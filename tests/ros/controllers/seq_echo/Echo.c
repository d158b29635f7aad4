/*
 * Echo.c: test controller, no arithmetic: the published sequence's length
 * is the received one (NS = L), its elements the received values (E0..E3
 * = V0..V3), the frame_id's length the same L and its bytes 'a', 'b'
 * (FL = L, F0 = 97, F1 = 98), and X = V0.
 */
#include "Echo.h"

ExtU_Echo_T Echo_U;
ExtY_Echo_T Echo_Y;

void Echo_step(void)
{
  Echo_Y.NS = Echo_U.L;
  Echo_Y.E0 = Echo_U.V0;
  Echo_Y.E1 = Echo_U.V1;
  Echo_Y.E2 = Echo_U.V2;
  Echo_Y.E3 = Echo_U.V3;
  Echo_Y.FL = Echo_U.L;
  Echo_Y.F0 = 97U;
  Echo_Y.F1 = 98U;
  Echo_Y.X = Echo_U.V0;
}

void Echo_initialize(void)
{
  Echo_Y.NS = 0U;
  Echo_Y.E0 = 0.0;
  Echo_Y.E1 = 0.0;
  Echo_Y.E2 = 0.0;
  Echo_Y.E3 = 0.0;
  Echo_Y.FL = 0U;
  Echo_Y.F0 = 0U;
  Echo_Y.F1 = 0U;
  Echo_Y.X = 0.0;
}
