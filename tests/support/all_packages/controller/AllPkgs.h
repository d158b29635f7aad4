/* AllPkgs.h: a controller with one input from each standard message
 * package (a pyrosgen test fixture). */
#ifndef RTW_HEADER_AllPkgs_h_
#define RTW_HEADER_AllPkgs_h_
#include "rtwtypes.h"
typedef struct {
  real_T StdIn;
  real_T Twist;
  real32_T Range;
  real_T Odom;
  uint8_T Goal;
  int8_T Diag;
  uint8_T Shape;
  real32_T Disparity;
  uint32_T TrajSeq;
  int32_T MarkerId;
  uint32_T ClockSec;
  int64_T TwoIntsA;
  boolean_T Param;
  boolean_T BondActive;
  uint8_T LoggerLevel[8];
} ExtU_AllPkgs_T;
typedef struct {
  real_T Out1;
} ExtY_AllPkgs_T;
extern ExtU_AllPkgs_T AllPkgs_U;
extern ExtY_AllPkgs_T AllPkgs_Y;
extern void AllPkgs_initialize(void);
extern void AllPkgs_step(void);
#endif
