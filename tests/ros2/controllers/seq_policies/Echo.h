/*
 * Echo.h: the test controller of tests/ros2/models/seq_policies.yaml
 * (Embedded Coder style): each output is an input, unchanged (Echo.c).
 */
#ifndef RTW_HEADER_Echo_h_
#define RTW_HEADER_Echo_h_

#include "rtwtypes.h"

typedef struct {
  real32_T R0;
  real32_T R1;
  real32_T R2;
  real32_T R3;
  uint32_T RN;
  boolean_T RT;
  uint8_T B0;
  uint8_T B1;
  uint8_T B2;
  uint8_T B3;
  uint8_T B4;
  uint8_T B5;
  uint8_T B6;
  uint8_T B7;
  uint32_T BN;
  boolean_T BT;
  real_T J0;
  real_T J1;
  real_T J2;
  real_T J3;
  uint32_T JN;
  uint8_T S0;
  uint8_T S7;
  uint32_T SN;
  uint32_T PL;
} ExtU_Echo_T;

typedef struct {
  real32_T X0;
  real32_T X1;
  real32_T X2;
  real32_T X3;
  uint32_T XN;
  boolean_T XT;
  uint8_T C0;
  uint8_T C1;
  uint8_T C2;
  uint8_T C3;
  uint8_T C4;
  uint8_T C5;
  uint8_T C6;
  uint8_T C7;
  uint32_T CN;
  boolean_T CT;
  real_T Q0;
  real_T Q1;
  real_T Q2;
  real_T Q3;
  uint32_T QN;
  uint8_T T0;
  uint8_T T7;
  uint32_T TN;
  uint32_T PN;
} ExtY_Echo_T;

extern ExtU_Echo_T Echo_U;
extern ExtY_Echo_T Echo_Y;

extern void Echo_initialize(void);
extern void Echo_step(void);

#endif /* RTW_HEADER_Echo_h_ */
