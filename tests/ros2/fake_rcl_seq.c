/* fake_rcl_seq.c: the driver of bench/runtime/fake_rcl.c (a fake rcl layer:
 * no DDS, no rmw) for the node of tests/ros2/models/seq_policies.yaml, in
 * tests/ros2/test_rcl_conversions_ros2.py.  It feeds the node's rcl wrapper
 * rosidl messages built from a schedule and prints every message the node
 * publishes, as the wrapper hands it to rcl_publish, so that the test can
 * compare, field by field, what the wrapper's conversions (to_c, from_c,
 * the policy-reject test) made of them with what the environment model says.
 *
 * The schedule (the file named by SEQ_SCHEDULE): one message a line,
 *   CYCLE TOPIC N V1 ... VN [M W1 ... WM]
 * TOPIC 0 /trunc (sensor_msgs/LaserScan: N ranges as float32 bits, M bytes
 * of header.frame_id), 1 /rej (std_msgs/Float64MultiArray: N float64
 * bits), 2 /rej_str (std_msgs/String: N bytes), 3 /publen
 * (std_msgs/UInt32: N is the value, no list).  A message is taken in its
 * cycle (at most one per topic and cycle), deserialized as rmw would: its
 * sequences and strings of exactly the schedule's length.
 *
 * The output: one line per published message,
 *   CYCLE TOPIC FIELDS...
 * floats as their bits in hex, integers in decimal, each sequence or string
 * as its size then its elements. */
#define _POSIX_C_SOURCE 200809L
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <geometry_msgs/msg/quaternion.h>
#include <rosidl_runtime_c/primitives_sequence_functions.h>
#include <rosidl_runtime_c/string_functions.h>
#include <sensor_msgs/msg/joy_feedback.h>
#include <sensor_msgs/msg/laser_scan.h>
#include <sensor_msgs/msg/region_of_interest.h>
#include <std_msgs/msg/bool.h>
#include <std_msgs/msg/float32_multi_array.h>
#include <std_msgs/msg/float64_multi_array.h>
#include <std_msgs/msg/header.h>
#include <std_msgs/msg/string.h>
#include <std_msgs/msg/u_int32.h>

#include "fake_rcl.h"

static const char *const TOPICS[] = {"/trunc", "/rej", "/rej_str", "/publen", "/echo/ranges", "/echo/frame",
                                     "/echo/flags", "/echo/rej", "/echo/str", "/echo/frame_truncated"};
#define NTOPICS 10

struct entry {
    long cycle;
    int topic;
    size_t n, m;
    unsigned long long *a, *b;
};

static struct entry *g_sched = NULL;
static size_t g_nsched = 0;
static int g_loaded = 0;

static void die(const char *what)
{
    fprintf(stderr, "fake_rcl_seq: %s\n", what);
    exit(3);
}

static unsigned long long *numbers(FILE *f, size_t n)
{
    unsigned long long *v = calloc(n + 1, sizeof *v);
    if (v == NULL) die("out of memory");
    for (size_t i = 0; i < n; ++i)
        if (fscanf(f, "%llx", &v[i]) != 1) die("bad schedule: a value is missing");
    return v;
}

static void load(void)
{
    const char *path = getenv("SEQ_SCHEDULE");
    FILE *f = path ? fopen(path, "r") : NULL;
    long cycle;
    int topic;
    if (f == NULL) die("SEQ_SCHEDULE names no readable file");
    while (fscanf(f, "%ld %d", &cycle, &topic) == 2) {
        struct entry e = {cycle, topic, 0, 0, NULL, NULL};
        if (topic < 0 || topic > 3 || fscanf(f, "%zu", &e.n) != 1) die("bad schedule line");
        if (topic != 3) e.a = numbers(f, e.n);
        if (topic == 0) {
            if (fscanf(f, "%zu", &e.m) != 1) die("bad schedule: no frame_id length");
            e.b = numbers(f, e.m);
        }
        g_sched = realloc(g_sched, (g_nsched + 1) * sizeof *g_sched);
        if (g_sched == NULL) die("out of memory");
        g_sched[g_nsched++] = e;
    }
    fclose(f);
    g_loaded = 1;
}

int bench_topic(const char *topic)
{
    for (int i = 0; i < NTOPICS; ++i)
        if (strcmp(topic, TOPICS[i]) == 0)
            return i;
    fprintf(stderr, "fake_rcl_seq: unknown topic %s\n", topic);
    exit(3);
}

static void string_of(rosidl_runtime_c__String *s, const unsigned long long *v, size_t n)
{
    char *buf = malloc(n + 1);
    if (buf == NULL) die("out of memory");
    for (size_t i = 0; i < n; ++i) buf[i] = (char)(unsigned char)v[i];
    if (!rosidl_runtime_c__String__assignn(s, buf, n)) die("String__assignn");
    free(buf);
}

int bench_take(int topic, void *msg, long cycle, unsigned long long *rx)
{
    const struct entry *e = NULL;
    if (!g_loaded) load();
    for (size_t i = 0; i < g_nsched && e == NULL; ++i)
        if (g_sched[i].cycle == cycle && g_sched[i].topic == topic) e = &g_sched[i];
    if (e == NULL) return 0;
    /* distinct, increasing receipt times: the merge calls the callbacks in topic order */
    *rx = 1000000000ULL + (unsigned long long)cycle * 20000000ULL + (unsigned long long)topic;
    if (topic == 0) {
        sensor_msgs__msg__LaserScan *m = msg;
        rosidl_runtime_c__float__Sequence__fini(&m->ranges);
        if (!rosidl_runtime_c__float__Sequence__init(&m->ranges, e->n)) die("float__Sequence__init");
        for (size_t i = 0; i < e->n; ++i) {
            uint32_t b = (uint32_t)e->a[i];
            memcpy(&m->ranges.data[i], &b, sizeof b);
        }
        string_of(&m->header.frame_id, e->b, e->m);
    } else if (topic == 1) {
        std_msgs__msg__Float64MultiArray *m = msg;
        rosidl_runtime_c__double__Sequence__fini(&m->data);
        if (!rosidl_runtime_c__double__Sequence__init(&m->data, e->n)) die("double__Sequence__init");
        for (size_t i = 0; i < e->n; ++i) memcpy(&m->data.data[i], &e->a[i], sizeof e->a[i]);
    } else if (topic == 2) {
        string_of(&((std_msgs__msg__String *)msg)->data, e->a, e->n);
    } else {
        ((std_msgs__msg__UInt32 *)msg)->data = (uint32_t)e->n;
    }
    return 1;
}

static unsigned f32bits(float x)
{
    uint32_t b;
    memcpy(&b, &x, sizeof b);
    return (unsigned)b;
}

static unsigned long long f64bits(double x)
{
    unsigned long long b;
    memcpy(&b, &x, sizeof b);
    return b;
}

static void print_string(const rosidl_runtime_c__String *s)
{
    printf(" %zu", s->size);
    for (size_t i = 0; i < s->size; ++i) printf(" %u", (unsigned)(unsigned char)s->data[i]);
}

void bench_published(int topic, const void *msg, long cycle)
{
    printf("%ld %s", cycle, TOPICS[topic]);
    if (topic == 4) {
        const std_msgs__msg__Float32MultiArray *m = msg;
        printf(" %zu %zu", m->layout.dim.size, (size_t)m->layout.data_offset);
        printf(" %zu", m->data.size);
        for (size_t i = 0; i < m->data.size; ++i) printf(" %08x", f32bits(m->data.data[i]));
    } else if (topic == 5) {
        const std_msgs__msg__Header *m = msg;
        printf(" %d %u", (int)m->stamp.sec, (unsigned)m->stamp.nanosec);
        print_string(&m->frame_id);
    } else if (topic == 6) {
        const sensor_msgs__msg__RegionOfInterest *m = msg;
        printf(" %u %u %u %u %d", (unsigned)m->x_offset, (unsigned)m->y_offset, (unsigned)m->height,
               (unsigned)m->width, m->do_rectify ? 1 : 0);
    } else if (topic == 7) {
        const geometry_msgs__msg__Quaternion *m = msg;
        printf(" %016llx %016llx %016llx %016llx", f64bits(m->x), f64bits(m->y), f64bits(m->z), f64bits(m->w));
    } else if (topic == 8) {
        const sensor_msgs__msg__JoyFeedback *m = msg;
        printf(" %u %u %08x", (unsigned)m->type, (unsigned)m->id, f32bits(m->intensity));
    } else if (topic == 9) {
        printf(" %d", ((const std_msgs__msg__Bool *)msg)->data ? 1 : 0);
    } else {
        die("a message published on a subscribed topic");
    }
    printf("\n");
}

void bench_report(long cycles)
{
    printf("cycles %ld\n", cycles);
    fflush(stdout);
    for (size_t i = 0; i < g_nsched; ++i) {
        free(g_sched[i].a);
        free(g_sched[i].b);
    }
    free(g_sched);
}
