/* pyrosgen init: an empty <string.h>: controller headers only need its macros, which are not read. */
