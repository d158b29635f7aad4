/* pyrosgen init: an empty <stdlib.h>: controller headers only need its macros, which are not read. */
