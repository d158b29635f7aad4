/*
 * ScanGuard.h: the controller of examples/scan_guard/scan_guard.yaml, in
 * the style of Simulink Embedded Coder (a model whose inport Scan is a
 * vector of 1081 single-precision ranges).
 *
 * Sample time: [0.05s, 0.0s]
 */
#ifndef RTW_HEADER_ScanGuard_h_
#define RTW_HEADER_ScanGuard_h_

#include "rtwtypes.h"

/* Sample time of the model (s) */
#define ScanGuard_SAMPLE_TIME          0.05

/* External inputs (root inport signals with default storage) */
typedef struct {
  real32_T Scan[1081];                 /* '<Root>/Scan' */
  uint32_T NScan;                      /* '<Root>/NScan' */
} ExtU_ScanGuard_T;

/* External outputs (root outports fed by signals with default storage) */
typedef struct {
  real_T Vx;                           /* '<Root>/Vx' */
  real32_T Closest;                    /* '<Root>/Closest' */
} ExtY_ScanGuard_T;

/* External inputs (root inport signals with default storage) */
extern ExtU_ScanGuard_T ScanGuard_U;

/* External outputs (root outports fed by signals with default storage) */
extern ExtY_ScanGuard_T ScanGuard_Y;

/* Model entry point functions */
extern void ScanGuard_initialize(void);
extern void ScanGuard_step(void);

#endif /* RTW_HEADER_ScanGuard_h_ */
