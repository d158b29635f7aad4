/*
 * ArmNamed.h: the controller of examples/arm_named/arm_named.yaml, in the
 * style of Simulink Embedded Coder (a model whose inports are vectors: six
 * joint names of 32 bytes, six positions, six velocities, six targets).
 *
 * Sample time: [0.01s, 0.0s]
 */
#ifndef RTW_HEADER_ArmNamed_h_
#define RTW_HEADER_ArmNamed_h_

#include "rtwtypes.h"

/* Sample time of the model (s) */
#define ArmNamed_SAMPLE_TIME           0.01

/* External inputs (root inport signals with default storage) */
typedef struct {
  uint8_T Name0[32];                   /* '<Root>/Name0' */
  uint8_T Name1[32];                   /* '<Root>/Name1' */
  uint8_T Name2[32];                   /* '<Root>/Name2' */
  uint8_T Name3[32];                   /* '<Root>/Name3' */
  uint8_T Name4[32];                   /* '<Root>/Name4' */
  uint8_T Name5[32];                   /* '<Root>/Name5' */
  uint32_T NNames;                     /* '<Root>/NNames' */
  real_T Pos[6];                       /* '<Root>/Pos' */
  uint32_T NPos;                       /* '<Root>/NPos' */
  real_T Vel[6];                       /* '<Root>/Vel' */
  uint32_T NVel;                       /* '<Root>/NVel' */
  real_T Target[6];                    /* '<Root>/Target' */
  uint32_T NTarget;                    /* '<Root>/NTarget' */
} ExtU_ArmNamed_T;

/* External outputs (root outports fed by signals with default storage) */
typedef struct {
  real_T Effort[6];                    /* '<Root>/Effort' */
  uint32_T NEffort;                    /* '<Root>/NEffort' */
} ExtY_ArmNamed_T;

/* External inputs (root inport signals with default storage) */
extern ExtU_ArmNamed_T ArmNamed_U;

/* External outputs (root outports fed by signals with default storage) */
extern ExtY_ArmNamed_T ArmNamed_Y;

/* Model entry point functions */
extern void ArmNamed_initialize(void);
extern void ArmNamed_step(void);

#endif /* RTW_HEADER_ArmNamed_h_ */
