/* fake_rcl_landshark.c: the driver of bench/runtime/fake_rcl.c for the
 * LandShark node (bench/ros2.py's instruction count): on each of the three
 * inputs one geometry_msgs/TwistStamped per cycle (twist.linear.x a value of
 * the cycle and the input, the rest of the message filled as a real sender
 * would: header.stamp, header.frame_id "odom", the other five velocities),
 * copied into the node's message with the rosidl __copy function (standing
 * for deserialization); every published base velocity folded, bit by bit,
 * into a 64-bit checksum (all six velocities, the stamp and the frame). */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <geometry_msgs/msg/twist_stamped.h>
#include <rosidl_runtime_c/string_functions.h>

#include "fake_rcl.h"

static const char *const TOPICS[] = {"/landshark/left_wheel_velocity", "/landshark/right_wheel_velocity",
                                     "/landshark/gps_velocity", "/landshark_control/base_velocity"};
#define NTOPICS 4

static geometry_msgs__msg__TwistStamped g_src;
static int g_src_up = 0;
static long g_published = 0;

int bench_topic(const char *topic)
{
    for (int i = 0; i < NTOPICS; ++i)
        if (strcmp(topic, TOPICS[i]) == 0)
            return i;
    fprintf(stderr, "fake_rcl_landshark: unknown topic %s\n", topic);
    exit(3);
}

int bench_take(int topic, void *msg, long cycle, unsigned long long *rx)
{
    if (topic > 2)
        return 0;
    if (!g_src_up) {
        memset(&g_src, 0, sizeof g_src);
        if (!geometry_msgs__msg__TwistStamped__init(&g_src) ||
            !rosidl_runtime_c__String__assign(&g_src.header.frame_id, "odom"))
            exit(3);
        g_src_up = 1;
    }
    g_src.header.stamp.sec = (int)(1000 + cycle / 50);
    g_src.header.stamp.nanosec = (unsigned)(cycle % 50) * 20000000U + (unsigned)topic;
    g_src.twist.linear.x = 1.0 + (double)cycle / 1024.0 + (double)topic * 0.25;
    g_src.twist.linear.y = -0.5 * (double)topic;
    g_src.twist.angular.z = 0.125 * (double)(cycle % 7);
    if (!geometry_msgs__msg__TwistStamped__copy(&g_src, (geometry_msgs__msg__TwistStamped *)msg))
        exit(3);
    *rx = 1000000000ULL * 1000ULL + (unsigned long long)cycle * 20000000ULL + (unsigned long long)topic * 1000ULL;
    return 1;
}

void bench_published(int topic, const void *msg, long cycle)
{
    const geometry_msgs__msg__TwistStamped *m = (const geometry_msgs__msg__TwistStamped *)msg;
    (void)cycle;
    fake_rcl_fold((unsigned long long)topic);
    fake_rcl_fold((unsigned long long)(unsigned)m->header.stamp.sec);
    fake_rcl_fold(m->header.stamp.nanosec);
    fake_rcl_fold_frame_and_twist(m);
    g_published++;
}

void bench_report(long cycles)
{
    printf("checksum %016llx published %ld cycles %ld\n", fake_rcl_checksum(), g_published, cycles);
    fflush(stdout);
}
