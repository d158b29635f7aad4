/*
 * ert_main.c
 *
 * Code generation for model "Rover": the example main program of the
 * generated code (a pyrosgen test fixture in the shape of Embedded
 * Coder's, written by hand).
 */
#include <stddef.h>
#include <stdio.h>               /* This example main program uses printf/fflush */
#include "Rover.h"                     /* Model header file */

/*
 * Associating rt_OneStep with a real-time clock or interrupt service routine
 * is what makes the generated code "real-time".  The function rt_OneStep is
 * always associated with the base rate of the model.
 */
void rt_OneStep(void);
void rt_OneStep(void)
{
  static boolean_T OverrunFlag = false;

  /* Check for overrun */
  if (OverrunFlag) {
    rtmSetErrorStatus(Rover_M, "Overrun");
    return;
  }

  OverrunFlag = true;

  /* Step the model */
  Rover_step();

  /* Indicate task complete */
  OverrunFlag = false;
}

/*
 * The example main function illustrates what is required by your
 * application code to initialize, execute, and terminate the generated code.
 */
int_T main(int_T argc, const char *argv[])
{
  /* Unused arguments */
  (void)(argc);
  (void)(argv);

  /* Initialize model */
  Rover_initialize();

  /* Attach rt_OneStep to a timer or interrupt service routine with
   * period 0.02 seconds (base rate of the model) here.
   * The call syntax for rt_OneStep is
   *
   *  rt_OneStep();
   */
  printf("Warning: The simulation will run forever. "
         "Generated ERT main won't simulate model step behavior. "
         "To change this behavior select the 'MAT-file logging' option.\n");
  fflush((NULL));
  while (rtmGetErrorStatus(Rover_M) == (NULL)) {
    /*  Perform application tasks here */
  }

  /* Terminate model */
  Rover_terminate();
  return 0;
}
