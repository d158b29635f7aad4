/* pyrosgen init: an empty <float.h>: controller headers only need its macros, which are not read. */
