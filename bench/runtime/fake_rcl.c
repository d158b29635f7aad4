/* fake_rcl.c: a fake rcl layer for bench/ros2.py's instruction counts (no
 * DDS, no rmw, no threads).  Linked into a ROS 2 node (the generated one:
 * its glue, its rcl wrapper <node>_rcl.c and its controller; or a
 * hand-written rcl node), before the real librcl, whose functions these
 * definitions replace for the executable (the others, rcl_clock_init,
 * rcl_clock_get_now, rcl_get_default_allocator, the rosidl __init/__fini
 * and __copy functions, stay the real ones):
 *
 * - rcl_init, rcl_node_init, rcl_subscription_init, rcl_publisher_init and
 *   their __fini, rcl_shutdown, rcl_context_fini, rcl_init_options_*: do
 *   nothing but remember each subscription's and publisher's topic;
 *   rcl_context_is_valid: true until rcl_shutdown;
 * - rcl_take: stands for the middleware's delivery and deserialization: at
 *   most one message per subscription and cycle, built in process by the
 *   node's driver (bench_take: a rosidl message __copy'd into the node's),
 *   with a received_timestamp; RCL_RET_SUBSCRIPTION_TAKE_FAILED otherwise;
 * - rcl_publish: stands for serialization and sending: hands the message
 *   to the driver (bench_published, which folds it into a checksum);
 * - clock_nanosleep (libc's, replaced for the executable): returns at once,
 *   having set the steady clock to the requested end of the period; each
 *   call ends a cycle; after BENCH_CYCLES cycles (environment, default
 *   1000) it raises SIGTERM, which both kinds of node handle by leaving
 *   their loop and finalizing;
 * - clock_gettime (libc's, replaced for the executable and the libraries):
 *   calls the real one (its cost is counted), then answers, for
 *   CLOCK_MONOTONIC, the steady clock of the simulation (which starts at
 *   1000 s and moves only in clock_nanosleep), so that a node is never late
 *   and every cycle runs the same code, whatever valgrind's slowness.
 *
 * At exit the driver prints its checksum (bench_report), so that the two
 * nodes can be checked to compute the same outputs.  bench/ros2.py counts
 * every instruction from main on (callgrind --toggle-collect) except inside
 * rcl_take, rcl_publish and clock_nanosleep (the middleware and the sleep)
 * and the controller's step function (the same code on both sides), and
 * the own instructions of clock_gettime here (libc's are counted). */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <geometry_msgs/msg/twist_stamped.h>
#include <rcl/rcl.h>

#include "fake_rcl.h"

#define FAKE_RCL_MAX 16

struct fake_endpoint {
    int topic;       /* the driver's index of the topic (bench_topic) */
    long taken_at;   /* the cycle of the last message taken, -1 before */
};

static struct fake_endpoint g_subs[FAKE_RCL_MAX], g_pubs[FAKE_RCL_MAX];
static int g_nsubs = 0, g_npubs = 0, g_valid = 0;
static long g_cycle = 0, g_cycles = -1;

long fake_rcl_cycle(void)
{
    return g_cycle;
}

static unsigned long long g_sum = 1469598103934665603ULL;

void fake_rcl_fold(unsigned long long v)
{
    g_sum = (g_sum ^ v) * 1099511628211ULL;
}

void fake_rcl_fold_double(double x)
{
    unsigned long long b;
    memcpy(&b, &x, sizeof b);
    fake_rcl_fold(b);
}

void fake_rcl_fold_frame_and_twist(const struct geometry_msgs__msg__TwistStamped *m)
{
    fake_rcl_fold(m->header.frame_id.size);
    for (size_t i = 0; i < m->header.frame_id.size; ++i)
        fake_rcl_fold((unsigned char)m->header.frame_id.data[i]);
    fake_rcl_fold_double(m->twist.linear.x);
    fake_rcl_fold_double(m->twist.linear.y);
    fake_rcl_fold_double(m->twist.linear.z);
    fake_rcl_fold_double(m->twist.angular.x);
    fake_rcl_fold_double(m->twist.angular.y);
    fake_rcl_fold_double(m->twist.angular.z);
}

unsigned long long fake_rcl_checksum(void)
{
    return g_sum;
}

static void at_exit_report(void)
{
    bench_report(g_cycle);
}

rcl_ret_t rcl_init_options_init(rcl_init_options_t *init_options, rcl_allocator_t allocator)
{
    (void)init_options;
    (void)allocator;
    return RCL_RET_OK;
}

rcl_ret_t rcl_init_options_fini(rcl_init_options_t *init_options)
{
    (void)init_options;
    return RCL_RET_OK;
}

rcl_ret_t rcl_init(int argc, char const *const *argv, const rcl_init_options_t *options, rcl_context_t *context)
{
    (void)argc;
    (void)argv;
    (void)options;
    (void)context;
    const char *s = getenv("BENCH_CYCLES");
    g_cycles = s && *s ? atol(s) : 1000;
    g_valid = 1;
    atexit(at_exit_report);
    return RCL_RET_OK;
}

bool rcl_context_is_valid(const rcl_context_t *context)
{
    (void)context;
    return g_valid != 0;
}

rcl_ret_t rcl_shutdown(rcl_context_t *context)
{
    (void)context;
    g_valid = 0;
    return RCL_RET_OK;
}

rcl_ret_t rcl_context_fini(rcl_context_t *context)
{
    (void)context;
    return RCL_RET_OK;
}

rcl_ret_t rcl_node_init(rcl_node_t *node, const char *name, const char *namespace_, rcl_context_t *context,
                        const rcl_node_options_t *options)
{
    (void)node;
    (void)name;
    (void)namespace_;
    (void)context;
    (void)options;
    return RCL_RET_OK;
}

rcl_ret_t rcl_node_fini(rcl_node_t *node)
{
    (void)node;
    return RCL_RET_OK;
}

static struct fake_endpoint *endpoint(struct fake_endpoint *table, int *n, const char *topic)
{
    if (*n >= FAKE_RCL_MAX) {
        fprintf(stderr, "fake_rcl: more than %d endpoints\n", FAKE_RCL_MAX);
        exit(3);
    }
    table[*n].topic = bench_topic(topic);
    table[*n].taken_at = -1;
    return &table[(*n)++];
}

rcl_ret_t rcl_subscription_init(rcl_subscription_t *subscription, const rcl_node_t *node,
                                const rosidl_message_type_support_t *type_support, const char *topic_name,
                                const rcl_subscription_options_t *options)
{
    (void)node;
    (void)type_support;
    (void)options;
    subscription->impl = (rcl_subscription_impl_t *)(void *)endpoint(g_subs, &g_nsubs, topic_name);
    return RCL_RET_OK;
}

rcl_ret_t rcl_subscription_fini(rcl_subscription_t *subscription, rcl_node_t *node)
{
    (void)node;
    subscription->impl = NULL;
    return RCL_RET_OK;
}

rcl_ret_t rcl_publisher_init(rcl_publisher_t *publisher, const rcl_node_t *node,
                             const rosidl_message_type_support_t *type_support, const char *topic_name,
                             const rcl_publisher_options_t *options)
{
    (void)node;
    (void)type_support;
    (void)options;
    publisher->impl = (rcl_publisher_impl_t *)(void *)endpoint(g_pubs, &g_npubs, topic_name);
    return RCL_RET_OK;
}

rcl_ret_t rcl_publisher_fini(rcl_publisher_t *publisher, rcl_node_t *node)
{
    (void)node;
    publisher->impl = NULL;
    return RCL_RET_OK;
}

rcl_ret_t rcl_take(const rcl_subscription_t *subscription, void *ros_message, rmw_message_info_t *message_info,
                   rmw_subscription_allocation_t *allocation)
{
    (void)allocation;
    struct fake_endpoint *e = (struct fake_endpoint *)(void *)subscription->impl;
    unsigned long long rx = 0;
    if (e->taken_at == g_cycle || !bench_take(e->topic, ros_message, g_cycle, &rx))
        return RCL_RET_SUBSCRIPTION_TAKE_FAILED;
    e->taken_at = g_cycle;
    if (message_info != NULL) {
        message_info->received_timestamp = (rmw_time_point_value_t)rx;
        message_info->source_timestamp = (rmw_time_point_value_t)rx;
    }
    return RCL_RET_OK;
}

rcl_ret_t rcl_publish(const rcl_publisher_t *publisher, const void *ros_message,
                      rmw_publisher_allocation_t *allocation)
{
    (void)allocation;
    const struct fake_endpoint *e = (const struct fake_endpoint *)(const void *)publisher->impl;
    bench_published(e->topic, ros_message, g_cycle);
    return RCL_RET_OK;
}

static struct timespec g_steady = {1000, 0};
static int (*g_real_clock_gettime)(clockid_t, struct timespec *) = 0;

int clock_gettime(clockid_t clock_id, struct timespec *tp)
{
    if (g_real_clock_gettime == 0) {
        void *sym = dlsym(RTLD_NEXT, "clock_gettime");
        memcpy(&g_real_clock_gettime, &sym, sizeof sym);   /* POSIX's way from object to function pointer */
        if (g_real_clock_gettime == 0) {
            fprintf(stderr, "fake_rcl: no clock_gettime after this one\n");
            exit(3);
        }
    }
    int rc = g_real_clock_gettime(clock_id, tp);
    if (rc == 0 && clock_id == CLOCK_MONOTONIC)
        *tp = g_steady;
    return rc;
}

int clock_nanosleep(clockid_t clock_id, int flags, const struct timespec *request, struct timespec *remain)
{
    (void)remain;
    if (clock_id == CLOCK_MONOTONIC && (flags & TIMER_ABSTIME) != 0 &&
        (request->tv_sec > g_steady.tv_sec || (request->tv_sec == g_steady.tv_sec && request->tv_nsec > g_steady.tv_nsec)))
        g_steady = *request;
    if (++g_cycle == g_cycles)
        raise(SIGTERM);
    return 0;
}
