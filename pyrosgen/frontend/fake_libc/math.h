/* pyrosgen init: an empty <math.h>: controller headers only need its macros, which are not read. */
