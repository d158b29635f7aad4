/* scan_guard_handwritten_rcl.c: the scan guard of
 * examples/scan_guard/scan_guard.yaml written by hand over rcl (ROS 2), the
 * reference of bench/ros2.py for the generated ROS 2 node, as
 * scan_guard_handwritten.cpp is for ROS 1.  The same controller (the
 * Embedded Coder C of examples/scan_guard/controller) and the same policy:
 *
 *   - one subscription to /scan (sensor_msgs/LaserScan, history depth 1);
 *     each cycle it takes what the subscription has and, for the newest
 *     scan, copies the first min(size, 1081) ranges, where they lie in the
 *     rosidl message, into ScanGuard_U.Scan, zeros after them (the model's
 *     relation `ranges -> Scan`, max_length 1081, policy truncate), and that
 *     length into ScanGuard_U.NScan;
 *   - ScanGuard_step(), then a geometry_msgs/TwistStamped on /cmd_vel in the
 *     frame base_link (assigned once: the message is kept from cycle to
 *     cycle) whose twist.linear.x is ScanGuard_Y.Vx, stamped with the ROS
 *     time (RCL_ROS_TIME) read after the take, and a std_msgs/Float32 on
 *     /closest whose data is ScanGuard_Y.Closest (history depth 1 both);
 *   - sleeps to the end of the period on the steady clock.
 *
 * With -DSCAN_GUARD_NO_STAMP the command is not stamped (header.stamp 0):
 * the model as bench/ros2.py built it while the ROS 2 target refused
 * `stamp: now` (DESIGN.md rule 4.17; it builds it with the stamp now).  Before the first scan the controller
 * sees zeros (ScanGuard_U is a zero-initialised global), as in the
 * generated node.
 *
 * usage: scan_guard_handwritten_rcl [PERIOD_MS]   (default 50, the model's) */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <rcl/rcl.h>
#include <rcl/error_handling.h>
#include <geometry_msgs/msg/twist_stamped.h>
#include <rosidl_runtime_c/string_functions.h>
#include <sensor_msgs/msg/laser_scan.h>
#include <std_msgs/msg/float32.h>

#include "ScanGuard.h"

#define MAX_RANGES (sizeof ScanGuard_U.Scan / sizeof ScanGuard_U.Scan[0])

static volatile sig_atomic_t stop = 0;
static void on_signal(int sig) { (void)sig; stop = 1; }

#define CHECK(x) do { rcl_ret_t rc_ = (x); if (rc_ != RCL_RET_OK) { \
    fprintf(stderr, "%s failed: %s\n", #x, rcl_get_error_string().str); exit(1); } } while (0)

static void use_scan(const sensor_msgs__msg__LaserScan *scan)
{
    const size_t n = scan->ranges.size < MAX_RANGES ? scan->ranges.size : MAX_RANGES;
    memcpy(ScanGuard_U.Scan, scan->ranges.data, n * sizeof ScanGuard_U.Scan[0]);
    memset(ScanGuard_U.Scan + n, 0, (MAX_RANGES - n) * sizeof ScanGuard_U.Scan[0]);
    ScanGuard_U.NScan = (uint32_T)n;
}

int main(int argc, char **argv)
{
    long long period = (argc > 1 ? atoll(argv[1]) : 50) * 1000000LL;
    rcl_allocator_t alloc = rcl_get_default_allocator();
    rcl_init_options_t io = rcl_get_zero_initialized_init_options();
    rcl_context_t ctx = rcl_get_zero_initialized_context();
    rcl_node_t node = rcl_get_zero_initialized_node();
    rcl_node_options_t no = rcl_node_get_default_options();
    rcl_subscription_t sub = rcl_get_zero_initialized_subscription();
    rcl_publisher_t cmd_pub = rcl_get_zero_initialized_publisher();
    rcl_publisher_t closest_pub = rcl_get_zero_initialized_publisher();
    rcl_clock_t ros_clock;
    sensor_msgs__msg__LaserScan scan;
    geometry_msgs__msg__TwistStamped cmd;
    std_msgs__msg__Float32 closest;
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    CHECK(rcl_init_options_init(&io, alloc));
    CHECK(rcl_init(0, NULL, &io, &ctx));
    CHECK(rcl_node_init(&node, "scan_guard_handwritten", "", &ctx, &no));
    CHECK(rcl_clock_init(RCL_ROS_TIME, &ros_clock, &alloc));
    memset(&scan, 0, sizeof scan);
    memset(&cmd, 0, sizeof cmd);
    memset(&closest, 0, sizeof closest);
    if (!sensor_msgs__msg__LaserScan__init(&scan) || !geometry_msgs__msg__TwistStamped__init(&cmd) ||
        !std_msgs__msg__Float32__init(&closest) ||
        !rosidl_runtime_c__String__assign(&cmd.header.frame_id, "base_link")) {
        fprintf(stderr, "message initialization failed\n");
        return 1;
    }
    rcl_subscription_options_t so = rcl_subscription_get_default_options();
    so.qos.depth = 1;
    CHECK(rcl_subscription_init(&sub, &node, ROSIDL_GET_MSG_TYPE_SUPPORT(sensor_msgs, msg, LaserScan), "/scan", &so));
    rcl_publisher_options_t po = rcl_publisher_get_default_options();
    po.qos.depth = 1;
    CHECK(rcl_publisher_init(&cmd_pub, &node, ROSIDL_GET_MSG_TYPE_SUPPORT(geometry_msgs, msg, TwistStamped),
                             "/cmd_vel", &po));
    CHECK(rcl_publisher_init(&closest_pub, &node, ROSIDL_GET_MSG_TYPE_SUPPORT(std_msgs, msg, Float32),
                             "/closest", &po));
    ScanGuard_initialize();
    struct timespec next;
    clock_gettime(CLOCK_MONOTONIC, &next);
    while (!stop) {
        int got = 0;
        while (rcl_take(&sub, &scan, NULL, NULL) == RCL_RET_OK) got = 1;
        if (got) use_scan(&scan);
#ifndef SCAN_GUARD_NO_STAMP
        rcl_time_point_value_t now = 0;
        CHECK(rcl_clock_get_now(&ros_clock, &now));
        cmd.header.stamp.sec = (int32_t)(now / 1000000000LL);
        cmd.header.stamp.nanosec = (uint32_t)(now % 1000000000LL);
#endif
        ScanGuard_step();
        cmd.twist.linear.x = ScanGuard_Y.Vx;
        CHECK(rcl_publish(&cmd_pub, &cmd, NULL));
        closest.data = ScanGuard_Y.Closest;
        CHECK(rcl_publish(&closest_pub, &closest, NULL));
        long long ns = next.tv_nsec + period;
        next.tv_sec += ns / 1000000000LL;
        next.tv_nsec = ns % 1000000000LL;
        while (!stop && clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL) == EINTR) {
        }
    }
    CHECK(rcl_subscription_fini(&sub, &node));
    CHECK(rcl_publisher_fini(&cmd_pub, &node));
    CHECK(rcl_publisher_fini(&closest_pub, &node));
    sensor_msgs__msg__LaserScan__fini(&scan);
    geometry_msgs__msg__TwistStamped__fini(&cmd);
    std_msgs__msg__Float32__fini(&closest);
    CHECK(rcl_clock_fini(&ros_clock));
    CHECK(rcl_node_fini(&node));
    CHECK(rcl_shutdown(&ctx));
    CHECK(rcl_context_fini(&ctx));
    CHECK(rcl_init_options_fini(&io));
    return 0;
}
