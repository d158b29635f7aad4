/*
 * Controller.h: a test controller for the LandShark node model, with the
 * interface of examples/landshark/controller/Controller.h (Embedded Coder
 * style) and a stateless, bit-exact step (see Controller.c), so that the
 * tests can predict every output bit for bit.
 */
#ifndef RTW_HEADER_Controller_h_
#define RTW_HEADER_Controller_h_

#include "rtwtypes.h"

typedef struct {
  real_T In1;
  real_T In2;
  real_T In3;
} ExtU_Controller_T;

typedef struct {
  real_T Out1;
} ExtY_Controller_T;

extern ExtU_Controller_T Controller_U;
extern ExtY_Controller_T Controller_Y;

extern void Controller_initialize(void);
extern void Controller_step(void);

#endif /* RTW_HEADER_Controller_h_ */
