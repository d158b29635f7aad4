/*
 * Rover.h
 *
 * Code generation for model "Rover": the median of three velocity
 * estimates, a PI law, and the referenced model "Wheel" saturating the
 * command (a pyrosgen test fixture in the shape of Embedded Coder's
 * <model>_ert_rtw/ folder, written by hand).
 */
#ifndef RTW_HEADER_Rover_h_
#define RTW_HEADER_Rover_h_
#ifndef Rover_COMMON_INCLUDES_
#define Rover_COMMON_INCLUDES_
#include "rtwtypes.h"
#include "rt_nonfinite.h"
#endif                                 /* Rover_COMMON_INCLUDES_ */

#include "Rover_types.h"

/* Child system includes */
#include "Wheel.h"
#include "rt_minsector.h"

/* Macros for accessing real-time model data structure */
#ifndef rtmGetErrorStatus
#define rtmGetErrorStatus(rtm)         ((rtm)->errorStatus)
#endif

#ifndef rtmSetErrorStatus
#define rtmSetErrorStatus(rtm, val)    ((rtm)->errorStatus = (val))
#endif

/* Block states (default storage) for system '<Root>' */
typedef struct {
  real_T Integrator_DSTATE;            /* '<Root>/Integrator' */
} DW_Rover_T;

/* External inputs (root inport signals with default storage) */
typedef struct {
  real_T In1;                          /* '<Root>/In1' */
  real_T In2;                          /* '<Root>/In2' */
  real_T In3;                          /* '<Root>/In3' */
} ExtU_Rover_T;

/* External outputs (root outports fed by signals with default storage) */
typedef struct {
  real_T Out1;                         /* '<Root>/Out1' */
} ExtY_Rover_T;

/* Real-time Model Data Structure */
struct tag_RTM_Rover_T {
  const char_T * volatile errorStatus;
};

/* Block states (default storage) */
extern DW_Rover_T Rover_DW;

/* External inputs (root inport signals with default storage) */
extern ExtU_Rover_T Rover_U;

/* External outputs (root outports fed by signals with default storage) */
extern ExtY_Rover_T Rover_Y;

/* Model entry point functions */
extern void Rover_initialize(void);
extern void Rover_step(void);
extern void Rover_terminate(void);

/* Real-time Model object */
extern RT_MODEL_Rover_T *const Rover_M;

/*-
 * The generated code includes comments that allow you to trace directly
 * back to the appropriate location in the model.  The basic format
 * is <system>/block_name, where system is the system number (uniquely
 * assigned by Simulink) and block_name is the name of the block.
 *
 * '<Root>' : 'Rover'
 * '<S1>'   : 'Rover/Model'
 */
#endif                                 /* RTW_HEADER_Rover_h_ */
