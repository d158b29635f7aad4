/*
 * Echo.h: the test controller of tests/ros/models/seq_echo.yaml (Embedded
 * Coder style): it passes a received length and four received values to
 * the length and the elements of a published sequence, and writes the
 * frame_id "ab" with the same length (see Echo.c).
 */
#ifndef RTW_HEADER_Echo_h_
#define RTW_HEADER_Echo_h_

#include "rtwtypes.h"

typedef struct {
  uint32_T L;
  real_T V0;
  real_T V1;
  real_T V2;
  real_T V3;
} ExtU_Echo_T;

typedef struct {
  uint32_T NS;
  real_T E0;
  real_T E1;
  real_T E2;
  real_T E3;
  uint32_T FL;
  uint8_T F0;
  uint8_T F1;
  real_T X;
} ExtY_Echo_T;

extern ExtU_Echo_T Echo_U;
extern ExtY_Echo_T Echo_Y;

extern void Echo_initialize(void);
extern void Echo_step(void);

#endif /* RTW_HEADER_Echo_h_ */
