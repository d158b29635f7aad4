/* fake_ros_laser_guard.c: the C ROS API of the laser guard's glue
 * (laser_guard_ros.h of pyrosgen build) without ROS, for counting the
 * instructions of the glue per cycle with callgrind (bench/laserscan.py),
 * as fake_ros_landshark.c does for LandShark.
 *
 * ros_ok() answers true BENCH_CYCLES times (environment variable, default
 * 1000); each ros_spinOnce() delivers one scan on /scan (the scans of
 * laser_scans.h in turn: shorter than 543 ranges, exactly 1081, longer),
 * converted as the wrapper converts a sensor_msgs::LaserScan (policy
 * truncate: len = min(size, 1081), truncated = size > 1081, the first len
 * ranges, zeros after them); the conversion is done once per scan at
 * start-up and is not part of the glue.  ros_time_sec() and
 * ros_time_nsec() are the wrapper's (from the time read at the last spin),
 * over a fake clock that advances 20 ms per cycle.  ros_publish_cmd_vel
 * folds the published command into a checksum printed at exit, so that
 * nothing is optimised away and the hand-written harness can be compared.
 *
 * With -DFAKE_SCAN_GUARD (and -DSCAN_GUARD_SCANS) it is the C ROS API of
 * the scan guard's glue (scan_guard_ros.h; bench/scan_guard.py): the same,
 * plus /closest (std_msgs/Float32), folded into the checksum too. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef FAKE_SCAN_GUARD
#include "scan_guard_types.h"
#else
#include "laser_guard_types.h"
#endif
#include "laser_scans.h"

typedef void (*cb_t)(struct sensor_msgs_LaserScan *);

static cb_t cb_scan;
static struct sensor_msgs_LaserScan scans[LASER_SCANS];
static long cycles = -1, cycle;
static double checksum;
static unsigned long long g_now_ns;

static void report(void)
{
    printf("cycles %ld checksum %.17g\n", cycle, checksum);
}

void ros_init(void)
{
    const char *s = getenv("BENCH_CYCLES");
    long k;
    cycles = s ? atol(s) : 1000;
    for (k = 0; k < LASER_SCANS; ++k) {
        struct sensor_msgs_LaserScan *c = &scans[k];
        unsigned n = laser_scan_length(k), len = n < 1081 ? n : 1081, i;
        memset(c, 0, sizeof *c);
        c->header.frame_id.len = LASER_FRAME_LEN;
        memcpy(c->header.frame_id.data, LASER_FRAME, LASER_FRAME_LEN);
        LASER_SCAN_SET_FIELDS(c);
        c->ranges.len = len;
        c->ranges.truncated = n > 1081;
        for (i = 0; i < len; ++i)
            c->ranges.data[i] = laser_scan_range(k, i);
    }
    g_now_ns = laser_clock_ns(0);
    atexit(report);
}

int ros_ok(void)
{
    return cycle < cycles;
}

void ros_spinOnce(void)
{
    struct sensor_msgs_LaserScan *c = &scans[cycle % LASER_SCANS];
    g_now_ns = laser_clock_ns(cycle);
    c->header.seq = (unsigned int)cycle;
    c->header.stamp.sec = (unsigned int)(g_now_ns / 1000000000ULL);
    cb_scan(c);
}

unsigned long long ros_now(void)
{
    return g_now_ns;
}

unsigned int ros_time_sec(void)
{
    return (unsigned int)(g_now_ns / 1000000000ULL);
}

unsigned int ros_time_nsec(void)
{
    return (unsigned int)(g_now_ns % 1000000000ULL);
}

void ros_rate_sleep(void)
{
    cycle++;
}

void ros_subscribe_scan(cb_t cb) { cb_scan = cb; }
void ros_advertise_cmd_vel(void) {}

void ros_publish_cmd_vel(struct geometry_msgs_TwistStamped *msg)
{
    unsigned len = msg->header.frame_id.len < 128 ? msg->header.frame_id.len : 128;
    laser_fold(&checksum, msg->header.seq, msg->header.stamp.sec, msg->header.stamp.nsec,
               msg->header.frame_id.data, len, msg->twist.linear.x, msg->twist.linear.y, msg->twist.linear.z,
               msg->twist.angular.x, msg->twist.angular.y, msg->twist.angular.z);
}

#ifdef FAKE_SCAN_GUARD
void ros_advertise_closest(void) {}

void ros_publish_closest(struct std_msgs_Float32 *msg)
{
    laser_fold_closest(&checksum, msg->data);
}
#endif
