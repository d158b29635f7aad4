// hw_harness.cpp: drives the hand-written LandShark node's per-cycle code
// (bench/handwritten/landshark_handwritten.cpp: its three callbacks and
// make_command) without ROS, for counting its instructions per cycle with
// callgrind, as fake_ros_landshark.c does for the generated glue
// (bench/runtime.py).  Each cycle: one new message on each topic handed to
// its callback (as roscpp hands a ConstPtr), Controller_step, and the
// command built and handed to a sink (hw_output), where the real node
// calls pub.publish.  BENCH_CYCLES cycles (default 1000).
// Link with landshark_handwritten.cpp compiled with
// -DLANDSHARK_HANDWRITTEN_NO_MAIN, the controller, and roscpp's libraries.
#include <geometry_msgs/TwistStamped.h>
#include <ros/serialization.h>

extern "C" {
#include "Controller.h"
}

// From landshark_handwritten.cpp, compiled on its own with
// -DLANDSHARK_HANDWRITTEN_NO_MAIN (so that nothing is inlined into this
// harness: each function is counted as the real node calls it).
void leftWheelCallback(const geometry_msgs::TwistStamped::ConstPtr &msg);
void rightWheelCallback(const geometry_msgs::TwistStamped::ConstPtr &msg);
void gpsCallback(const geometry_msgs::TwistStamped::ConstPtr &msg);
geometry_msgs::TwistStamped make_command();

#include <boost/make_shared.hpp>
#include <cstdio>
#include <cstdlib>
#include <string>

static double g_checksum;

__attribute__((noinline)) void sink(const geometry_msgs::TwistStamped &c)
{
    g_checksum += c.twist.linear.x + c.twist.linear.y + double(c.header.seq);
}

// What the real node's loop does with make_command(): build the message,
// hand it over, destroy it.
__attribute__((noinline)) void hw_output()
{
    sink(make_command());
}

// For scale: what roscpp itself does with such a message, once per
// message received (deserialize) and once per message published
// (serialize), in the real nodes (BENCH_MODE=roscpp).
__attribute__((noinline)) void roscpp_roundtrip(const geometry_msgs::TwistStamped &in,
                                                geometry_msgs::TwistStamped &out)
{
    namespace ser = ros::serialization;
    uint8_t buf[256];
    const uint32_t n = ser::serializationLength(in);
    ser::OStream os(buf, n);
    ser::serialize(os, in);
    ser::IStream is(buf, n);
    ser::deserialize(is, out);
}

int main()
{
    const char *mode = std::getenv("BENCH_MODE");
    const bool roscpp = mode && std::string(mode) == "roscpp";
    const char *s = std::getenv("BENCH_CYCLES");
    long cycles = s ? std::atol(s) : 1000;
    geometry_msgs::TwistStamped::Ptr l = boost::make_shared<geometry_msgs::TwistStamped>();
    geometry_msgs::TwistStamped::Ptr r = boost::make_shared<geometry_msgs::TwistStamped>();
    geometry_msgs::TwistStamped::Ptr g = boost::make_shared<geometry_msgs::TwistStamped>();
    geometry_msgs::TwistStamped::ConstPtr cl = l, cr = r, cg = g;
    Controller_initialize();
    long cycle;
    for (cycle = 0; cycle < cycles; ++cycle) {
        double v = double(cycle % 7) * 0.25;
        l->header.seq = r->header.seq = g->header.seq = unsigned(cycle);
        l->twist.linear.x = v;
        r->twist.linear.x = v + 0.125;
        g->twist.linear.x = v - 0.125;
        leftWheelCallback(cl);
        rightWheelCallback(cr);
        gpsCallback(cg);
        Controller_step();
        hw_output();
        if (roscpp) {
            geometry_msgs::TwistStamped cmd = make_command(), back;
            roscpp_roundtrip(cmd, back);
            g_checksum += back.twist.linear.x;
        }
    }
    std::printf("cycles %ld checksum %.17g\n", cycle, g_checksum);
    return 0;
}
