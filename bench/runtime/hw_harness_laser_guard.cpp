// hw_harness_laser_guard.cpp: drives the hand-written laser guard's
// per-cycle code (bench/handwritten/laser_guard_handwritten.cpp: its scan
// callback and make_command) without ROS, for counting its instructions
// per cycle with callgrind, as fake_ros_laser_guard.c does for the
// generated glue (bench/laserscan.py); hw_harness.cpp does the same for
// LandShark.  Each cycle: one scan (those of laser_scans.h in turn, with
// their real lengths: the callback does the capping) handed to the callback
// as roscpp hands it (a ConstPtr), Guard_step, and the command built and
// handed to a sink (hw_output) where the real node calls pub.publish.
// ros::Time::now() runs on simulated time (ros::Time::setNow before each
// cycle, outside the counted functions) so that both harnesses stamp the
// same times.  BENCH_CYCLES cycles (default 1000).
// Link with laser_guard_handwritten.cpp compiled with
// -DLASER_GUARD_HANDWRITTEN_NO_MAIN, the controller, and roscpp's libraries.
#include <geometry_msgs/TwistStamped.h>
#include <sensor_msgs/LaserScan.h>
#include <ros/serialization.h>
#include <ros/time.h>

extern "C" {
#include "Guard.h"
}
#include "laser_scans.h"

// From laser_guard_handwritten.cpp, compiled on its own (so that nothing is
// inlined into this harness: each function is counted as the real node
// calls it).
void scanCallback(const sensor_msgs::LaserScan::ConstPtr &msg);
geometry_msgs::TwistStamped make_command();

#include <boost/make_shared.hpp>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

static double g_checksum;

__attribute__((noinline)) void sink(const geometry_msgs::TwistStamped &c)
{
    const std::string &f = c.header.frame_id;
    laser_fold(&g_checksum, c.header.seq, c.header.stamp.sec, c.header.stamp.nsec,
               reinterpret_cast<const unsigned char *>(f.data()), unsigned(f.size()), c.twist.linear.x,
               c.twist.linear.y, c.twist.linear.z, c.twist.angular.x, c.twist.angular.y, c.twist.angular.z);
}

// What the real node's loop does with make_command(): build the message,
// hand it over, destroy it.
__attribute__((noinline)) void hw_output()
{
    sink(make_command());
}

// For scale: what roscpp itself does with a scan, once per scan received
// (serialize in the sender, deserialize in the node), BENCH_MODE=roscpp.
__attribute__((noinline)) void roscpp_roundtrip(const sensor_msgs::LaserScan &in, sensor_msgs::LaserScan &out,
                                                std::vector<uint8_t> &buf)
{
    namespace ser = ros::serialization;
    const uint32_t n = ser::serializationLength(in);
    buf.resize(n);
    ser::OStream os(buf.data(), n);
    ser::serialize(os, in);
    ser::IStream is(buf.data(), n);
    ser::deserialize(is, out);
}

int main()
{
    const char *mode = std::getenv("BENCH_MODE");
    const bool roscpp = mode && std::string(mode) == "roscpp";
    const char *s = std::getenv("BENCH_CYCLES");
    long cycles = s ? std::atol(s) : 1000;
    std::vector<sensor_msgs::LaserScan::Ptr> scans;
    for (long k = 0; k < LASER_SCANS; ++k) {
        sensor_msgs::LaserScan::Ptr m = boost::make_shared<sensor_msgs::LaserScan>();
        m->header.frame_id = LASER_FRAME;
        m->angle_min = -2.35619449f;
        m->angle_max = 2.35619449f;
        m->angle_increment = 0.00436332313f;
        m->scan_time = 0.025f;
        m->range_min = 0.1f;
        m->range_max = 30.0f;
        m->ranges.resize(laser_scan_length(k));
        for (unsigned i = 0; i < m->ranges.size(); ++i) m->ranges[i] = laser_scan_range(k, i);
        scans.push_back(m);
    }
    ros::Time::init();
    Guard_initialize();
    sensor_msgs::LaserScan back;
    std::vector<uint8_t> buf;
    long cycle;
    for (cycle = 0; cycle < cycles; ++cycle) {
        const sensor_msgs::LaserScan::Ptr &m = scans[cycle % LASER_SCANS];
        ros::Time now;
        now.fromNSec(laser_clock_ns(cycle));
        ros::Time::setNow(now);
        m->header.seq = unsigned(cycle);
        m->header.stamp.sec = now.sec;
        sensor_msgs::LaserScan::ConstPtr cm = m;
        scanCallback(cm);
        Guard_step();
        hw_output();
        if (roscpp) {
            roscpp_roundtrip(*m, back, buf);
        }
    }
    std::printf("cycles %ld checksum %.17g\n", cycle, g_checksum);
    return 0;
}
