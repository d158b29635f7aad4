/*
 * Robot.h
 *
 * Code generation for model "Robot": stop when an obstacle is nearer than
 * the safe distance in any of four sectors, else drive at the cruise
 * speed when enabled (a pyrosgen test fixture in the shape of Embedded
 * Coder's <model>_ert_rtw/ folder, written by hand).
 */
#ifndef RTW_HEADER_Robot_h_
#define RTW_HEADER_Robot_h_
#ifndef Robot_COMMON_INCLUDES_
#define Robot_COMMON_INCLUDES_
#include "rtwtypes.h"
#endif                                 /* Robot_COMMON_INCLUDES_ */

#include "Robot_types.h"
#include "rt_nonfinite.h"

/* Macros for accessing real-time model data structure */
#ifndef rtmGetErrorStatus
#define rtmGetErrorStatus(rtm)         ((rtm)->errorStatus)
#endif

#ifndef rtmSetErrorStatus
#define rtmSetErrorStatus(rtm, val)    ((rtm)->errorStatus = (val))
#endif

/* External inputs (root inport signals with default storage) */
typedef struct {
  real32_T Sectors[4];                 /* '<Root>/Sectors': nearest range in each sector, m */
  boolean_T Enable;                    /* '<Root>/Enable' */
} ExtU_Robot_T;

/* External outputs (root outports fed by signals with default storage) */
typedef struct {
  real_T Speed;                        /* '<Root>/Speed': commanded speed, m/s */
  uint8_T Mode;                        /* '<Root>/Mode': 0 stopped, 1 driving */
} ExtY_Robot_T;

/* Parameters (default storage) */
struct P_Robot_T_ {
  real32_T SafeDistance;               /* Variable: SafeDistance
                                        * Referenced by: '<Root>/Compare'
                                        */
  real_T Cruise;                       /* Variable: Cruise
                                        * Referenced by: '<Root>/Cruise'
                                        */
};

/* Real-time Model Data Structure */
struct tag_RTM_Robot_T {
  const char_T * volatile errorStatus;
};

/* Block parameters (default storage) */
extern P_Robot_T Robot_P;

/* External inputs (root inport signals with default storage) */
extern ExtU_Robot_T Robot_U;

/* External outputs (root outports fed by signals with default storage) */
extern ExtY_Robot_T Robot_Y;

/* Model entry point functions */
extern void Robot_initialize(void);
extern void Robot_step(void);
extern void Robot_terminate(void);

/* Real-time Model object */
extern RT_MODEL_Robot_T *const Robot_M;

#endif                                 /* RTW_HEADER_Robot_h_ */
