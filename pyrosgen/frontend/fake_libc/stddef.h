/* pyrosgen init: a minimal <stddef.h> for reading controller headers with pycparser. */
#ifndef PYROSGEN_FAKE_STDDEF_H
#define PYROSGEN_FAKE_STDDEF_H
typedef unsigned long size_t;
typedef long ptrdiff_t;
typedef int wchar_t;
#define NULL 0
#endif
