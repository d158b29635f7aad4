/* stub_controller_landshark.c: a controller for counting the LandShark
 * glue's instructions with and without a timed topic (bench/freshness.py):
 * the globals of the glue's header and a step that reads every input, so
 * that nothing is optimised away.  Its own instructions are not counted.
 * -DBENCH_FRESH: the inputs have a fourth field, GpsAge
 * (bench/models/landshark_fresh.yaml). */
#include "landshark_controller_types.h"

struct ExtU_Controller_T Controller_U;
struct ExtY_Controller_T Controller_Y;

void Controller_initialize(void)
{
}

void Controller_step(void)
{
    Controller_Y.Out1 = Controller_U.In1 + Controller_U.In2 + Controller_U.In3
#ifdef BENCH_FRESH
        + (double)Controller_U.GpsAge
#endif
        ;
}
