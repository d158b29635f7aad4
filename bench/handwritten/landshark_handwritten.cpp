// landshark_handwritten.cpp: the LandShark node of the paper's Table 1
// written by hand in idiomatic roscpp, as the baseline of the run-time
// benchmarks (BENCHMARKS.md, section 3).  It does what the node generated
// by pyrosgen from examples/landshark/landshark_controller.yaml does, with
// the same Simulink-style controller (examples/landshark/controller):
//
//   - three subscriptions (queue 1), whose callbacks store twist.linear.x
//     of the newest message into Controller_U.In1..In3;
//   - a loop at a fixed rate: spinOnce, Controller_step, publish a
//     TwistStamped whose twist.linear.x is Controller_Y.Out1.
//
// The period is the private parameter ~period_ms (default 20, the model's;
// the benchmark runs both nodes at 1 ms).  Like the generated node, it
// publishes messages with every other field zero (no stamp).
//
// Built by bench/runtime.py:
//   g++ -std=c++14 -O2 landshark_handwritten.cpp Controller.c $(pkg-config --cflags --libs roscpp geometry_msgs)
// With -DLANDSHARK_HANDWRITTEN_NO_MAIN it only defines the callbacks and
// make_command(), for the instruction-count harness (bench/runtime/).

#include <ros/ros.h>
#include <geometry_msgs/TwistStamped.h>

extern "C" {
#include "Controller.h"
}

void leftWheelCallback(const geometry_msgs::TwistStamped::ConstPtr &msg)
{
    Controller_U.In1 = msg->twist.linear.x;
}

void rightWheelCallback(const geometry_msgs::TwistStamped::ConstPtr &msg)
{
    Controller_U.In2 = msg->twist.linear.x;
}

void gpsCallback(const geometry_msgs::TwistStamped::ConstPtr &msg)
{
    Controller_U.In3 = msg->twist.linear.x;
}

// The command of this cycle, from the controller's output.
geometry_msgs::TwistStamped make_command()
{
    geometry_msgs::TwistStamped cmd;
    cmd.twist.linear.x = Controller_Y.Out1;
    return cmd;
}

#ifndef LANDSHARK_HANDWRITTEN_NO_MAIN
int main(int argc, char **argv)
{
    ros::init(argc, argv, "landshark_handwritten");
    ros::NodeHandle nh;
    ros::NodeHandle pnh("~");
    double period_ms = 20.0;
    pnh.param("period_ms", period_ms, period_ms);

    Controller_initialize();
    ros::Subscriber left = nh.subscribe("/landshark/left_wheel_velocity", 1, leftWheelCallback);
    ros::Subscriber right = nh.subscribe("/landshark/right_wheel_velocity", 1, rightWheelCallback);
    ros::Subscriber gps = nh.subscribe("/landshark/gps_velocity", 1, gpsCallback);
    ros::Publisher pub = nh.advertise<geometry_msgs::TwistStamped>("/landshark_control/base_velocity", 1);

    ros::Rate rate(1000.0 / period_ms);
    while (ros::ok()) {
        ros::spinOnce();
        Controller_step();
        pub.publish(make_command());
        rate.sleep();
    }
    return 0;
}
#endif
