/*
 * ArmNamed.c: a joint-space PD controller for a 6-joint arm that finds its
 * joints by name (examples/arm_named).
 *
 * A sensor_msgs/JointState lists its joints in the driver's order, not the
 * controller's: joint j of the controller (JOINT[j] below, the names of a
 * UR arm) is the entry i of the message whose name is JOINT[j].  Name_i
 * holds the first 32 bytes of the message's name[i], zero after its end;
 * an entry counts only below the received lengths (NNames, NPos, NVel).
 * When every joint is found and the target holds six angles,
 *   Effort[j] = sat(KP * (Target[j] - Pos[i]) - KD * Vel[i]),
 * saturated to [-EMAX, EMAX] N m, with NEffort = 6; else no command
 * (NEffort = 0, Effort all 0).
 */
#include "ArmNamed.h"

#define KP    20.0
#define KD    2.0
#define EMAX  50.0
#define NAME  32

ExtU_ArmNamed_T ArmNamed_U;
ExtY_ArmNamed_T ArmNamed_Y;

static const char *const JOINT[6] = {
  "shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
  "wrist_1_joint", "wrist_2_joint", "wrist_3_joint"
};

/* Whether a received name (32 bytes, zero after its end) is exactly `s`:
   the bytes of `s`, then zeros up to the 32nd.  A name of 32 bytes or more
   never matches (every joint name is shorter). */
static boolean_T name_is(const uint8_T *name, const char *s)
{
  int k;
  for (k = 0; s[k] != '\0'; k++) {
    if (k >= NAME - 1 || name[k] != (uint8_T)s[k]) {
      return 0U;
    }
  }
  for (; k < NAME; k++) {
    if (name[k] != 0U) {
      return 0U;
    }
  }
  return 1U;
}

static const uint8_T *entry_name(int i)
{
  switch (i) {
   case 0: return ArmNamed_U.Name0;
   case 1: return ArmNamed_U.Name1;
   case 2: return ArmNamed_U.Name2;
   case 3: return ArmNamed_U.Name3;
   case 4: return ArmNamed_U.Name4;
   default: return ArmNamed_U.Name5;
  }
}

void ArmNamed_step(void)
{
  int j, i;
  int index[6];
  boolean_T ok = ArmNamed_U.NTarget >= 6U;
  for (j = 0; j < 6 && ok; j++) {
    index[j] = -1;
    for (i = 0; i < 6; i++) {
      if ((uint32_T)i < ArmNamed_U.NNames && (uint32_T)i < ArmNamed_U.NPos
          && (uint32_T)i < ArmNamed_U.NVel && name_is(entry_name(i), JOINT[j])) {
        index[j] = i;
        break;
      }
    }
    ok = index[j] >= 0;
  }
  for (j = 0; j < 6; j++) {
    real_T e = 0.0;
    if (ok) {
      i = index[j];
      e = KP * (ArmNamed_U.Target[j] - ArmNamed_U.Pos[i]) - KD * ArmNamed_U.Vel[i];
      e = e > EMAX ? EMAX : (e < -EMAX ? -EMAX : e);
    }
    ArmNamed_Y.Effort[j] = e;
  }
  ArmNamed_Y.NEffort = ok ? 6U : 0U;
}

void ArmNamed_initialize(void)
{
  int j;
  for (j = 0; j < 6; j++) {
    ArmNamed_Y.Effort[j] = 0.0;
  }
  ArmNamed_Y.NEffort = 0U;
}
