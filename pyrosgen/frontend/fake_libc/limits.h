/* pyrosgen init: an empty <limits.h>: controller headers only need its macros, which are not read. */
