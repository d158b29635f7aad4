/* pyrosgen init: a minimal <stdbool.h> for reading controller headers with pycparser. */
#ifndef PYROSGEN_FAKE_STDBOOL_H
#define PYROSGEN_FAKE_STDBOOL_H
#define bool _Bool
#define true 1
#define false 0
#endif
