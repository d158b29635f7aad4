/* pyrosgen init: an empty <stdio.h>: controller headers only need its macros, which are not read. */
