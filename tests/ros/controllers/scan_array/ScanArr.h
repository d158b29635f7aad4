/*
 * ScanArr.h: the test controller of tests/ros/models/scan_array.yaml
 * (Embedded Coder style, with vector inports and outports as array
 * members: rule 4.15's controller arrays); see ScanArr.c.
 */
#ifndef RTW_HEADER_ScanArr_h_
#define RTW_HEADER_ScanArr_h_

#include "rtwtypes.h"

typedef struct {
  real32_T Scan[8];                    /* '<Root>/Scan' */
  uint32_T NScan;                      /* '<Root>/NScan' */
  real32_T Last[2];                    /* '<Root>/Last' */
} ExtU_ScanArr_T;

typedef struct {
  real32_T Echo[8];                    /* '<Root>/Echo' */
  uint32_T NEcho;                      /* '<Root>/NEcho' */
  real32_T Pt[3];                      /* '<Root>/Pt' */
} ExtY_ScanArr_T;

extern ExtU_ScanArr_T ScanArr_U;
extern ExtY_ScanArr_T ScanArr_Y;

extern void ScanArr_initialize(void);
extern void ScanArr_step(void);

#endif /* RTW_HEADER_ScanArr_h_ */
