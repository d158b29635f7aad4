// fake_ros_scan_guard_wrapper.cpp: the scan guard's C ROS API (the
// generated scan_guard_ros.h) with the generated wrapper's own per-message
// code and roscpp's transport replaced by a fake, for counting with
// callgrind what the glue costs together with the wrapper's conversions
// (bench/scan_guard.py; BENCHMARKS.md section 11).  fake_ros_laser_guard.c
// built with -DFAKE_SCAN_GUARD hands the glue scans already converted; this
// file converts each one as the built node does.
//
// bench/scan_guard.py extracts from the wrapper that `pyrosgen build` wrote
// (scan_guard_ros.cpp) and writes next to the object:
//   - scan_guard_wrapper_conversions.inc: the wrapper's conversions between
//     roscpp messages and the C structs (every to_c/from_c), verbatim;
//   - scan_guard_wrapper_functions.inc: verbatim, the body of the lambda
//     that ros_subscribe_scan hands roscpp (as the body of
//     wrapper_scan_received below: receipt time, zeroed C struct, to_c,
//     the glue's callback), and the functions ros_spinOnce (as
//     wrapper_ros_spinOnce, its call of ros::spinOnce() dropped: the fake's
//     transport, fake_spin_once, runs just before), ros_now, ros_time_sec,
//     ros_time_nsec, ros_publish_cmd_vel and ros_publish_closest (roscpp
//     message built from the C struct by from_c, handed to publish(),
//     destroyed).
// Compiled as the wrapper is (-std=c++14 -O2).
//
// The fake transport: each ros_spinOnce() delivers one scan of
// laser_scans.h (-DSCAN_GUARD_SCANS: the scan guard's lengths) as roscpp
// does, a ros::MessageEvent holding the shared message, with simulated ROS
// time (ros::Time::setNow: 1 s + 20 ms per cycle), so that the stamps are
// those of the other harnesses.  The publishers stand for ros::Publisher:
// publish() hands the message to sink(), which folds it into the checksum
// printed at exit (the same as fake_ros_laser_guard.c's and
// hw_harness_laser_guard.cpp's).  BENCH_CYCLES cycles (default 1000).
#include <ros/message_event.h>
#include <ros/time.h>
#include <geometry_msgs/Twist.h>
#include <geometry_msgs/TwistStamped.h>
#include <geometry_msgs/Vector3.h>
#include <sensor_msgs/LaserScan.h>
#include <std_msgs/Float32.h>
#include <std_msgs/Header.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "scan_guard_ros.h"
#include "laser_scans.h"

static double g_checksum;

// roscpp's publish (not counted: outside the namespace the wrapper's code
// lives in, so that callgrind names it plain "sink" as the hand-written
// harness's).
__attribute__((noinline)) void sink(const geometry_msgs::TwistStamped &c)
{
    laser_fold_twist(&g_checksum, c);
}

__attribute__((noinline)) void sink(const std_msgs::Float32 &c)
{
    laser_fold_closest(&g_checksum, c.data);
}

namespace {

// Stands for ros::Publisher (the wrapper's g_pub_<topic>.publish(r)).
struct FakePublisher {
    template <class M>
    void publish(const M &m) const { sink(m); }
};

// The wrapper's globals that its per-message code uses.
unsigned long long g_now_ns = 0;
FakePublisher g_pub_cmd_vel;
FakePublisher g_pub_closest;

#include "scan_guard_wrapper_conversions.inc"

void (*g_cb_scan)(struct sensor_msgs_LaserScan *);
std::vector<sensor_msgs::LaserScan::Ptr> g_scans;
long g_cycles = 1000, g_cycle = 0;

void report()
{
    std::printf("cycles %ld checksum %.17g\n", g_cycle, g_checksum);
}

}  // namespace

// The body of the wrapper's subscription lambda, verbatim.
__attribute__((noinline)) void wrapper_scan_received(void (*cb)(struct sensor_msgs_LaserScan *),
                                                     const ros::MessageEvent<sensor_msgs::LaserScan const> &e);
// ros_spinOnce of the wrapper without its ros::spinOnce() call, verbatim.
__attribute__((noinline)) void wrapper_ros_spinOnce();

// roscpp's part of a spin: the next scan, as roscpp hands it (not counted).
__attribute__((noinline)) void fake_spin_once()
{
    ros::Time now;
    const sensor_msgs::LaserScan::Ptr &m = laser_scan_of_cycle(g_scans, g_cycle, &now);
    const ros::MessageEvent<sensor_msgs::LaserScan const> e(sensor_msgs::LaserScan::ConstPtr(m), now);
    wrapper_scan_received(g_cb_scan, e);
}

#include "scan_guard_wrapper_functions.inc"

extern "C" {

void ros_init(void)
{
    const char *s = std::getenv("BENCH_CYCLES");
    g_cycles = s ? std::atol(s) : 1000;
    g_scans = laser_scan_messages();
    ros::Time::init();
    ros::Time t;
    t.fromNSec(laser_clock_ns(0));
    ros::Time::setNow(t);
    g_now_ns = ros::Time::now().toNSec();
    std::atexit(report);
}

int ros_ok(void)
{
    return g_cycle < g_cycles;
}

void ros_spinOnce(void)
{
    fake_spin_once();
    wrapper_ros_spinOnce();
}

void ros_rate_sleep(void)
{
    ++g_cycle;
}

void ros_subscribe_scan(void (*cb)(struct sensor_msgs_LaserScan *))
{
    g_cb_scan = cb;
}

void ros_advertise_cmd_vel(void) {}
void ros_advertise_closest(void) {}

}  // extern "C"
