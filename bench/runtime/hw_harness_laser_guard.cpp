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
//
// With -DHW_SCAN_GUARD (and -DSCAN_GUARD_SCANS) it drives the hand-written
// scan guard instead (bench/handwritten/scan_guard_handwritten.cpp built
// with -DSCAN_GUARD_HANDWRITTEN_NO_MAIN; bench/scan_guard.py): the same,
// with the ScanGuard controller and, each cycle, the /closest Float32 built
// by make_closest() and handed to the sink too.
#include <geometry_msgs/TwistStamped.h>
#include <sensor_msgs/LaserScan.h>
#include <ros/serialization.h>
#include <ros/time.h>

#ifdef HW_SCAN_GUARD
#include <std_msgs/Float32.h>
extern "C" {
#include "ScanGuard.h"
}
#define CONTROLLER_INITIALIZE ScanGuard_initialize
#define CONTROLLER_STEP ScanGuard_step
#else
extern "C" {
#include "Guard.h"
}
#define CONTROLLER_INITIALIZE Guard_initialize
#define CONTROLLER_STEP Guard_step
#endif
#include "laser_scans.h"

// From laser_guard_handwritten.cpp (scan_guard_handwritten.cpp), compiled
// on its own (so that nothing is inlined into this harness: each function
// is counted as the real node calls it).
void scanCallback(const sensor_msgs::LaserScan::ConstPtr &msg);
geometry_msgs::TwistStamped make_command();
#ifdef HW_SCAN_GUARD
std_msgs::Float32 make_closest();
#endif

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

static double g_checksum;

__attribute__((noinline)) void sink(const geometry_msgs::TwistStamped &c)
{
    laser_fold_twist(&g_checksum, c);
}

#ifdef HW_SCAN_GUARD
__attribute__((noinline)) void sink(const std_msgs::Float32 &c)
{
    laser_fold_closest(&g_checksum, c.data);
}
#endif

// What the real node's loop does with make_command() (and make_closest()):
// build the message, hand it over, destroy it.
__attribute__((noinline)) void hw_output()
{
    sink(make_command());
#ifdef HW_SCAN_GUARD
    sink(make_closest());
#endif
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
    const std::vector<sensor_msgs::LaserScan::Ptr> scans = laser_scan_messages();
    ros::Time::init();
    CONTROLLER_INITIALIZE();
    sensor_msgs::LaserScan back;
    std::vector<uint8_t> buf;
    long cycle;
    for (cycle = 0; cycle < cycles; ++cycle) {
        ros::Time now;
        const sensor_msgs::LaserScan::Ptr &m = laser_scan_of_cycle(scans, cycle, &now);
        sensor_msgs::LaserScan::ConstPtr cm = m;
        scanCallback(cm);
        CONTROLLER_STEP();
        hw_output();
        if (roscpp) {
            roscpp_roundtrip(*m, back, buf);
        }
    }
    std::printf("cycles %ld checksum %.17g\n", cycle, g_checksum);
    return 0;
}
