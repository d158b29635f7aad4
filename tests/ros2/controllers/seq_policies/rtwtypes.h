/*
 * rtwtypes.h: the Simulink Embedded Coder base types used by Controller.h.
 * Written for pyrosgen's LandShark example (a subset of what Embedded Coder emits).
 */
#ifndef RTWTYPES_H
#define RTWTYPES_H

typedef signed char int8_T;
typedef unsigned char uint8_T;
typedef short int16_T;
typedef unsigned short uint16_T;
typedef int int32_T;
typedef unsigned int uint32_T;
typedef long long int64_T;
typedef unsigned long long uint64_T;
typedef float real32_T;
typedef double real64_T;
typedef double real_T;
typedef unsigned char boolean_T;

#endif /* RTWTYPES_H */
