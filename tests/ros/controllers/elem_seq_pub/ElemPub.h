/*
 * ElemPub.h: the test controller of tests/ros/models/elem_seq_pub.yaml
 * (Embedded Coder style): it passes received lengths and values to the
 * elements of a published Path and JointState (see ElemPub.c).
 */
#ifndef RTW_HEADER_ElemPub_h_
#define RTW_HEADER_ElemPub_h_

#include "rtwtypes.h"

typedef struct {
  uint32_T L;
  uint32_T S;
  real_T V0;
  real_T V1;
  real_T V2;
} ExtU_ElemPub_T;

typedef struct {
  uint32_T NP;
  real_T X0;
  real_T X1;
  real_T X2;
  uint32_T Q1;
  uint32_T FL1;
  uint8_T F10;
  uint8_T F11;
  uint32_T NJ;
  uint32_T N0L;
  uint8_T N0[4];
  uint32_T N2L;
  uint8_T N2B0;
} ExtY_ElemPub_T;

extern ExtU_ElemPub_T ElemPub_U;
extern ExtY_ElemPub_T ElemPub_Y;

extern void ElemPub_initialize(void);
extern void ElemPub_step(void);

#endif /* RTW_HEADER_ElemPub_h_ */
