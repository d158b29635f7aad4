#include "AllPkgs.h"
ExtU_AllPkgs_T AllPkgs_U;
ExtY_AllPkgs_T AllPkgs_Y;
void AllPkgs_initialize(void) { AllPkgs_Y.Out1 = 0.0; }
void AllPkgs_step(void)
{
  AllPkgs_Y.Out1 = AllPkgs_U.StdIn + AllPkgs_U.Twist + AllPkgs_U.Range + AllPkgs_U.Odom + AllPkgs_U.Goal
    + AllPkgs_U.Diag + AllPkgs_U.Shape + AllPkgs_U.Disparity + AllPkgs_U.TrajSeq + AllPkgs_U.MarkerId
    + AllPkgs_U.ClockSec + (real_T)AllPkgs_U.TwoIntsA + AllPkgs_U.Param + AllPkgs_U.BondActive
    + AllPkgs_U.LoggerLevel[0];
}
