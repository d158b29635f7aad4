/*
 * Controller.c: test controller. The bits of Out1 are
 *     bits(In1) ^ rotl(bits(In2), 21) ^ rotl(bits(In3), 42) ^ bits(1.0)
 * (no floating-point arithmetic: NaN payloads and signed zeros go through),
 * so every input bit reaches the output and all-zero inputs give 1.0.
 * tests/ros/test_e2e.py computes the same function in Python.
 */
#include <string.h>
#include "Controller.h"

ExtU_Controller_T Controller_U;
ExtY_Controller_T Controller_Y;

static unsigned long long bits(real_T x)
{
  unsigned long long b;
  memcpy(&b, &x, sizeof b);
  return b;
}

static unsigned long long rotl(unsigned long long b, unsigned n)
{
  return (b << n) | (b >> (64U - n));
}

void Controller_step(void)
{
  unsigned long long b = bits(Controller_U.In1) ^ rotl(bits(Controller_U.In2), 21U)
    ^ rotl(bits(Controller_U.In3), 42U) ^ 0x3FF0000000000000ULL;
  memcpy(&Controller_Y.Out1, &b, sizeof b);
}

void Controller_initialize(void)
{
  Controller_Y.Out1 = 0.0;
}
