/*
 * Fusion.h: sensor fusion and safety controller for examples/multi.
 *
 * Written for pyrosgen in the style of Simulink Embedded Coder output
 * (ExtU_<model>_T / ExtY_<model>_T, <model>_U / <model>_Y, <model>_initialize,
 * <model>_step). Inputs: odometry, IMU, a front range sensor and an
 * emergency-stop message. Outputs: a velocity command and a status report.
 */
#ifndef RTW_HEADER_Fusion_h_
#define RTW_HEADER_Fusion_h_

#include "rtwtypes.h"

/* External inputs (root inport signals with default storage) */
typedef struct {
  real_T X;                            /* '<Root>/X': odometry position x, m */
  real_T Y;                            /* '<Root>/Y': odometry position y, m */
  real_T YawVar;                       /* '<Root>/YawVar': odometry yaw variance, rad^2 */
  real_T YawRate;                      /* '<Root>/YawRate': odometry yaw rate, rad/s */
  uint32_T OdomSeq;                    /* '<Root>/OdomSeq': odometry header sequence */
  real_T GyroZ;                        /* '<Root>/GyroZ': IMU yaw rate, rad/s */
  real_T AccX;                         /* '<Root>/AccX': IMU forward acceleration, m/s^2 */
  real32_T FrontRange;                 /* '<Root>/FrontRange': front distance, m */
  uint8_T RangeType;                   /* '<Root>/RangeType': 0 ultrasound, 1 infrared */
  boolean_T EStop;                     /* '<Root>/EStop': emergency stop engaged */
  int32_T HoldSec;                     /* '<Root>/HoldSec': seconds the stop has been held */
} ExtU_Fusion_T;

/* External outputs (root outports fed by signals with default storage) */
typedef struct {
  real_T CmdV;                         /* '<Root>/CmdV': forward velocity command, m/s */
  real_T CmdW;                         /* '<Root>/CmdW': yaw rate command, rad/s */
  boolean_T Stopped;                   /* '<Root>/Stopped': the robot is held */
  uint32_T SeqOut;                     /* '<Root>/SeqOut': last odometry sequence used */
  real_T YawVarOut;                    /* '<Root>/YawVarOut': yaw variance used */
  real32_T WheelCmd;                   /* '<Root>/WheelCmd': wheel speed command, rad/s */
  real_T Debug;                        /* '<Root>/Debug': fused yaw rate, rad/s */
} ExtY_Fusion_T;

/* Block states (default storage) */
typedef struct {
  real_T FusedRate_DSTATE;             /* '<S1>/Filter' */
} DW_Fusion_T;

/* Tunable parameters */
#define Fusion_VMAX          (0.8)     /* m/s */
#define Fusion_KRANGE        (0.5)     /* 1/s: speed per metre of free range */
#define Fusion_STOP_US       (0.40)    /* m: stop distance, ultrasound */
#define Fusion_STOP_IR       (0.25)    /* m: stop distance, infrared */
#define Fusion_GYRO_VAR      (0.0025)  /* rad^2: gyro variance */
#define Fusion_ALPHA         (0.2)     /* low-pass filter coefficient */
#define Fusion_KW            (0.5)     /* yaw damping gain */
#define Fusion_WHEEL_RADIUS  (0.1)     /* m */

extern ExtU_Fusion_T Fusion_U;
extern ExtY_Fusion_T Fusion_Y;
extern DW_Fusion_T Fusion_DW;

extern void Fusion_initialize(void);
extern void Fusion_step(void);
extern void Fusion_terminate(void);

#endif /* RTW_HEADER_Fusion_h_ */
