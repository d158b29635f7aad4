/*
 * Fusion.h: a test controller for examples/multi/multi_node.yaml, with the
 * interface of examples/multi/controller/Fusion.h and a stateless,
 * bit-exact step (see Fusion.c).
 */
#ifndef RTW_HEADER_Fusion_h_
#define RTW_HEADER_Fusion_h_

#include "rtwtypes.h"

typedef struct {
  real_T X;
  real_T Y;
  real_T YawVar;
  real_T YawRate;
  uint32_T OdomSeq;
  real_T GyroZ;
  real_T AccX;
  real32_T FrontRange;
  uint8_T RangeType;
  boolean_T EStop;
  int32_T HoldSec;
} ExtU_Fusion_T;

typedef struct {
  real_T CmdV;
  real_T CmdW;
  boolean_T Stopped;
  uint32_T SeqOut;
  real_T YawVarOut;
  real32_T WheelCmd;
  real_T Debug;
} ExtY_Fusion_T;

extern ExtU_Fusion_T Fusion_U;
extern ExtY_Fusion_T Fusion_Y;

extern void Fusion_initialize(void);
extern void Fusion_step(void);

#endif /* RTW_HEADER_Fusion_h_ */
