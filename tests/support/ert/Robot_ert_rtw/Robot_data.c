/*
 * Robot_data.c
 *
 * Code generation for model "Robot": its block parameters (a pyrosgen
 * test fixture).
 */
#include "Robot.h"

/* Block parameters (default storage) */
P_Robot_T Robot_P = {
  /* Variable: SafeDistance
   * Referenced by: '<Root>/Compare'
   */
  0.5F,

  /* Variable: Cruise
   * Referenced by: '<Root>/Cruise'
   */
  0.4
};
