/* fake_ros_landshark.c: the C ROS API of the LandShark glue
 * (<node>_ros.h of pyrosgen build) without ROS, for counting the
 * instructions of the glue per cycle with callgrind (bench/runtime.py).
 *
 * ros_ok() answers true BENCH_CYCLES times (environment variable, default
 * 1000); each ros_spinOnce() delivers one new message on each of the three
 * subscribed topics (values change every cycle); ros_publish_* folds the
 * published command into a checksum printed at exit, so that nothing is
 * optimised away.  The glue's own main() and loop() drive everything.
 *
 * For bench/freshness.py: -DBENCH_GPS_GAPS delivers the GPS message only
 * in the first 8 cycles of every 16 (with a 100 ms timeout and 20 ms
 * cycles the topic is then stale in 3 cycles of 16); -DBENCH_FRESH adds
 * ros_now(), the time of a fake clock that advances 20 ms per cycle. */
#include <stdio.h>
#include <stdlib.h>
#include "landshark_controller_types.h"

typedef void (*cb_t)(struct geometry_msgs_TwistStamped *);

static cb_t cb_left, cb_right, cb_gps;
static struct geometry_msgs_TwistStamped m_left, m_right, m_gps;
static long cycles = -1, cycle;
static double checksum;

static void report(void)
{
    printf("cycles %ld checksum %.17g\n", cycle, checksum);
}

void ros_init(void)
{
    const char *s = getenv("BENCH_CYCLES");
    cycles = s ? atol(s) : 1000;
    atexit(report);
}

int ros_ok(void)
{
    return cycle < cycles;
}

void ros_spinOnce(void)
{
    double v = (double)(cycle % 7) * 0.25;
    m_left.header.seq = m_right.header.seq = m_gps.header.seq = (unsigned int)cycle;
    m_left.twist.linear.x = v;
    m_right.twist.linear.x = v + 0.125;
    m_gps.twist.linear.x = v - 0.125;
    cb_left(&m_left);
    cb_right(&m_right);
#ifdef BENCH_GPS_GAPS
    if (cycle % 16 < 8)
#endif
    cb_gps(&m_gps);
}

#ifdef BENCH_FRESH
unsigned long long ros_now(void)
{
    return 1000000000ULL + (unsigned long long)cycle * 20000000ULL;
}
#endif

void ros_rate_sleep(void)
{
    cycle++;
}

void ros_subscribe_landshark_left_wheel_velocity(cb_t cb) { cb_left = cb; }
void ros_subscribe_landshark_right_wheel_velocity(cb_t cb) { cb_right = cb; }
void ros_subscribe_landshark_gps_velocity(cb_t cb) { cb_gps = cb; }
void ros_advertise_landshark_control_base_velocity(void) {}

void ros_publish_landshark_control_base_velocity(struct geometry_msgs_TwistStamped *msg)
{
    checksum += msg->twist.linear.x + msg->twist.linear.y + (double)msg->header.seq;
}
