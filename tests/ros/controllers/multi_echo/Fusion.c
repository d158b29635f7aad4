/*
 * Fusion.c: test controller, stateless and bit-exact (no floating-point
 * arithmetic); tests/ros/test_e2e.py computes the same function in Python:
 *   CmdV      = bits(X) ^ rotl(bits(Y), 13) ^ rotl(bits(GyroZ), 29) ^ bits(1.0)
 *   CmdW      = bits(YawRate) ^ rotl(bits(AccX), 7) ^ bits(2.0)
 *   Stopped   = (EStop ^ RangeType ^ 1) & 1
 *   SeqOut    = OdomSeq ^ (uint32)HoldSec ^ (RangeType << 24) ^ 0xA5A5A5A5
 *   YawVarOut = bits(YawVar) ^ bits(3.0)
 *   WheelCmd  = FrontRange (a copy)
 *   Debug     = bits(X) (not published)
 */
#include <string.h>
#include "Fusion.h"

ExtU_Fusion_T Fusion_U;
ExtY_Fusion_T Fusion_Y;

static uint64_T bits(real_T x)
{
  uint64_T b;
  memcpy(&b, &x, sizeof b);
  return b;
}

static real_T from_bits(uint64_T b)
{
  real_T x;
  memcpy(&x, &b, sizeof x);
  return x;
}

static uint64_T rotl(uint64_T b, unsigned n)
{
  return (b << n) | (b >> (64U - n));
}

void Fusion_step(void)
{
  Fusion_Y.CmdV = from_bits(bits(Fusion_U.X) ^ rotl(bits(Fusion_U.Y), 13U)
                            ^ rotl(bits(Fusion_U.GyroZ), 29U) ^ 0x3FF0000000000000ULL);
  Fusion_Y.CmdW = from_bits(bits(Fusion_U.YawRate) ^ rotl(bits(Fusion_U.AccX), 7U)
                            ^ 0x4000000000000000ULL);
  Fusion_Y.Stopped = (boolean_T)(((unsigned)Fusion_U.EStop ^ (unsigned)Fusion_U.RangeType ^ 1U) & 1U);
  Fusion_Y.SeqOut = Fusion_U.OdomSeq ^ (uint32_T)Fusion_U.HoldSec
    ^ ((uint32_T)Fusion_U.RangeType << 24) ^ 0xA5A5A5A5U;
  Fusion_Y.YawVarOut = from_bits(bits(Fusion_U.YawVar) ^ 0x4008000000000000ULL);
  memcpy(&Fusion_Y.WheelCmd, &Fusion_U.FrontRange, sizeof Fusion_Y.WheelCmd);
  Fusion_Y.Debug = from_bits(bits(Fusion_U.X));
}

void Fusion_initialize(void)
{
}
