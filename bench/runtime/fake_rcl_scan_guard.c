/* fake_rcl_scan_guard.c: the driver of bench/runtime/fake_rcl.c for the
 * scan guard (bench/ros2.py's instruction count): one sensor_msgs/LaserScan
 * per cycle on /scan, the scans of bench/runtime/laser_scans.h (built with
 * -DSCAN_GUARD_SCANS: lengths 0, 1, 600, 601, 1080, 1081 three times, 1082
 * and 2000 in turn, or every scan BENCH_SCAN_LENGTH long; header.frame_id
 * "laser" and the other fields set), copied into the node's message with
 * the rosidl __copy function (standing for deserialization); every
 * published /cmd_vel (geometry_msgs/TwistStamped) and /closest
 * (std_msgs/Float32) folded, bit by bit, into a 64-bit checksum: the frame,
 * the six velocities, whether the stamp is set (its value is the ROS
 * clock's, which differs from run to run), the closest range. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <geometry_msgs/msg/twist_stamped.h>
#include <rosidl_runtime_c/primitives_sequence_functions.h>
#include <rosidl_runtime_c/string_functions.h>
#include <sensor_msgs/msg/laser_scan.h>
#include <std_msgs/msg/float32.h>

#include "fake_rcl.h"
#include "laser_scans.h"

static const char *const TOPICS[] = {"/scan", "/cmd_vel", "/closest"};
#define NTOPICS 3

static sensor_msgs__msg__LaserScan g_scans[LASER_SCANS];
static int g_scans_up = 0;
static long g_published = 0;

int bench_topic(const char *topic)
{
    for (int i = 0; i < NTOPICS; ++i)
        if (strcmp(topic, TOPICS[i]) == 0)
            return i;
    fprintf(stderr, "fake_rcl_scan_guard: unknown topic %s\n", topic);
    exit(3);
}

static void make_scans(void)
{
    for (long k = 0; k < LASER_SCANS; ++k) {
        sensor_msgs__msg__LaserScan *m = &g_scans[k];
        unsigned n = laser_scan_length(k);
        memset(m, 0, sizeof *m);
        if (!sensor_msgs__msg__LaserScan__init(m) || !rosidl_runtime_c__String__assign(&m->header.frame_id, LASER_FRAME) ||
            !rosidl_runtime_c__float__Sequence__init(&m->ranges, n))
            exit(3);
        LASER_SCAN_SET_FIELDS(m);
        for (unsigned i = 0; i < n; ++i)
            m->ranges.data[i] = laser_scan_range(k, i);
    }
    g_scans_up = 1;
}

int bench_take(int topic, void *msg, long cycle, unsigned long long *rx)
{
    if (topic != 0)
        return 0;
    if (!g_scans_up)
        make_scans();
    sensor_msgs__msg__LaserScan *m = &g_scans[cycle % LASER_SCANS];
    unsigned long long t = laser_clock_ns(cycle);
    m->header.stamp.sec = (int)(t / 1000000000ULL);
    m->header.stamp.nanosec = (unsigned)(t % 1000000000ULL);
    if (!sensor_msgs__msg__LaserScan__copy(m, (sensor_msgs__msg__LaserScan *)msg))
        exit(3);
    *rx = t;
    return 1;
}

void bench_published(int topic, const void *msg, long cycle)
{
    (void)cycle;
    fake_rcl_fold((unsigned long long)topic);
    if (topic == 1) {
        const geometry_msgs__msg__TwistStamped *m = (const geometry_msgs__msg__TwistStamped *)msg;
        fake_rcl_fold(m->header.stamp.sec != 0 || m->header.stamp.nanosec != 0);
        fake_rcl_fold_frame_and_twist(m);
    } else {
        const std_msgs__msg__Float32 *m = (const std_msgs__msg__Float32 *)msg;
        unsigned b;
        memcpy(&b, &m->data, sizeof b);
        fake_rcl_fold(b);
    }
    g_published++;
}

void bench_report(long cycles)
{
    printf("checksum %016llx published %ld cycles %ld\n", fake_rcl_checksum(), g_published, cycles);
    fflush(stdout);
}
