/* landshark_handwritten_rcl.c: the LandShark node written by hand over rcl
 * (bench/ros2.py's reference for the generated ROS 2 node): three
 * subscriptions of geometry_msgs/TwistStamped with history depth 1, a loop
 * that takes what each has (keeping twist.linear.x of the newest into
 * Controller_U), runs Controller_step() and publishes a TwistStamped whose
 * twist.linear.x is Controller_Y.Out1, then sleeps to the end of the period
 * on the steady clock.  The rosidl messages are read where they lie.
 * usage: landshark_handwritten_rcl [PERIOD_MS]   (default 20) */
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

#include "Controller.h"

static volatile sig_atomic_t stop = 0;
static void on_signal(int sig) { (void)sig; stop = 1; }

#define CHECK(x) do { rcl_ret_t rc_ = (x); if (rc_ != RCL_RET_OK) { \
    fprintf(stderr, "%s failed: %s\n", #x, rcl_get_error_string().str); exit(1); } } while (0)

int main(int argc, char **argv)
{
    long long period = (argc > 1 ? atoll(argv[1]) : 20) * 1000000LL;
    static const char *topics[3] = {"/landshark/left_wheel_velocity", "/landshark/right_wheel_velocity",
                                    "/landshark/gps_velocity"};
    rcl_allocator_t alloc = rcl_get_default_allocator();
    rcl_init_options_t io = rcl_get_zero_initialized_init_options();
    rcl_context_t ctx = rcl_get_zero_initialized_context();
    rcl_node_t node = rcl_get_zero_initialized_node();
    rcl_node_options_t no = rcl_node_get_default_options();
    rcl_subscription_t subs[3];
    rcl_publisher_t pub = rcl_get_zero_initialized_publisher();
    geometry_msgs__msg__TwistStamped in, out;
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    CHECK(rcl_init_options_init(&io, alloc));
    CHECK(rcl_init(0, NULL, &io, &ctx));
    CHECK(rcl_node_init(&node, "landshark_handwritten", "", &ctx, &no));
    memset(&in, 0, sizeof in);
    memset(&out, 0, sizeof out);
    geometry_msgs__msg__TwistStamped__init(&in);
    geometry_msgs__msg__TwistStamped__init(&out);
    for (int i = 0; i < 3; ++i) {
        rcl_subscription_options_t so = rcl_subscription_get_default_options();
        so.qos.depth = 1;
        subs[i] = rcl_get_zero_initialized_subscription();
        CHECK(rcl_subscription_init(&subs[i], &node, ROSIDL_GET_MSG_TYPE_SUPPORT(geometry_msgs, msg, TwistStamped),
                                    topics[i], &so));
    }
    rcl_publisher_options_t po = rcl_publisher_get_default_options();
    po.qos.depth = 1;
    CHECK(rcl_publisher_init(&pub, &node, ROSIDL_GET_MSG_TYPE_SUPPORT(geometry_msgs, msg, TwistStamped),
                             "/landshark_control/base_velocity", &po));
    Controller_initialize();
    struct timespec next;
    clock_gettime(CLOCK_MONOTONIC, &next);
    while (!stop) {
        for (int i = 0; i < 3; ++i) {
            while (rcl_take(&subs[i], &in, NULL, NULL) == RCL_RET_OK) {
                double x = in.twist.linear.x;
                if (i == 0) Controller_U.In1 = x; else if (i == 1) Controller_U.In2 = x; else Controller_U.In3 = x;
            }
        }
        Controller_step();
        out.twist.linear.x = Controller_Y.Out1;
        CHECK(rcl_publish(&pub, &out, NULL));
        long long ns = next.tv_nsec + period;
        next.tv_sec += ns / 1000000000LL;
        next.tv_nsec = ns % 1000000000LL;
        while (!stop && clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL) == EINTR) {
        }
    }
    for (int i = 0; i < 3; ++i) CHECK(rcl_subscription_fini(&subs[i], &node));
    CHECK(rcl_publisher_fini(&pub, &node));
    geometry_msgs__msg__TwistStamped__fini(&in);
    geometry_msgs__msg__TwistStamped__fini(&out);
    CHECK(rcl_node_fini(&node));
    CHECK(rcl_shutdown(&ctx));
    CHECK(rcl_context_fini(&ctx));
    CHECK(rcl_init_options_fini(&io));
    return 0;
}
