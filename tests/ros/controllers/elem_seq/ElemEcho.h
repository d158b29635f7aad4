/*
 * ElemEcho.h: the test controller of tests/ros/models/elem_seq.yaml
 * (Embedded Coder style: vector inports and outports as array members): it
 * publishes every input back as one float64 array (see ElemEcho.c).
 */
#ifndef RTW_HEADER_ElemEcho_h_
#define RTW_HEADER_ElemEcho_h_

#include "rtwtypes.h"

typedef struct {
  uint32_T NP;
  boolean_T TP;
  real_T P0X;
  real_T P2W;
  uint32_T P1S;
  uint8_T P1F0;
  uint32_T P1FL;
  boolean_T P1FT;
  uint8_T F2[4];
  uint32_T NJ;
  boolean_T TJ;
  uint32_T N0L;
  boolean_T N0T;
  uint8_T N2B3;
  uint8_T N1[4];
} ExtU_ElemEcho_T;

typedef struct {
  uint32_T NOut;
  real_T Out[21];
} ExtY_ElemEcho_T;

extern ExtU_ElemEcho_T ElemEcho_U;
extern ExtY_ElemEcho_T ElemEcho_Y;

extern void ElemEcho_initialize(void);
extern void ElemEcho_step(void);

#endif /* RTW_HEADER_ElemEcho_h_ */
