/* time_probe_glue.c: a hand-written C "glue" for the wrapper of
 * time_probe.yaml, recording what ros_now() answers (tests/ros/test_ros_time.py).
 *
 * The callback of /probe/in reads ros_now() (the receipt time of the message
 * it is handed) twice, and the message's sequence number (linear.x).  The
 * loop reads ros_now() before ros_spinOnce() (the previous cycle's time, or
 * ros_init's before the first spin) and after it (this cycle's time), and
 * publishes one nav_msgs/Odometry per cycle:
 *
 *   header.seq          the cycle number (0, 1, ...)
 *   header.stamp        the cycle time: ros_now() after ros_spinOnce(), as
 *                       ros_time_sec() and ros_time_nsec() give it
 *   pose.covariance[k]  k = 0, 1: the receipt time of the newest message
 *                                 (high, low 32 bits; 0 if none yet)
 *                       k = 2:    the newest message's sequence number (-1 if none)
 *                       k = 3, 4: ros_now() before this cycle's ros_spinOnce()
 *                       k = 5, 6: ros_now() right after ros_init()
 *                       k = 7:    callbacks so far
 *                       k = 8:    callbacks during this cycle's spin
 *                       k = 9, 10: the earliest receipt time during this spin
 *                       k = 11:   callbacks in which two reads of ros_now() differed
 *                       k = 12:   callbacks whose receipt time was before the previous one's
 *                       k = 13, 14: ros_now() before the first cycle's ros_spinOnce()
 *                       k = 15:   reads where ros_time_sec()/ros_time_nsec() were not
 *                                 the seconds/nanoseconds of ros_now() (callbacks and cycles)
 *
 * A 64-bit time travels as two doubles of 32 bits each (exact). */
#include "time_probe_ros.h"

static unsigned long long init_time;
static unsigned long long first_before;
static unsigned long long newest_receipt;
static double newest_seq = -1.0;
static unsigned long long callbacks;
static unsigned long long spin_callbacks;
static unsigned long long spin_min_receipt;
static unsigned long long unstable;
static unsigned long long backwards;
static unsigned long long split_errors;
static struct nav_msgs_Odometry out;

static void put_time(unsigned long long t, int k)
{
    out.pose.covariance[k] = (double)(t >> 32);
    out.pose.covariance[k + 1] = (double)(t & 0xFFFFFFFFULL);
}

/* ros_time_sec() and ros_time_nsec() against ros_now() */
static void check_split(void)
{
    unsigned long long t = ros_now();
    if (ros_time_sec() != (unsigned int)(t / 1000000000ULL) || ros_time_nsec() != (unsigned int)(t % 1000000000ULL)) {
        split_errors++;
    }
}

static void probe_in(struct geometry_msgs_Twist *msg)
{
    unsigned long long t = ros_now();
    check_split();
    if (ros_now() != t) {
        unstable++;
    }
    if (callbacks > 0 && t < newest_receipt) {
        backwards++;
    }
    if (spin_callbacks == 0 || t < spin_min_receipt) {
        spin_min_receipt = t;
    }
    newest_receipt = t;
    newest_seq = msg->linear.x;
    callbacks++;
    spin_callbacks++;
}

int main(void)
{
    unsigned int cycle = 0;
    ros_init();
    init_time = ros_now();
    ros_subscribe_probe_in(&probe_in);
    ros_advertise_probe_out();
    while (ros_ok()) {
        unsigned long long before = ros_now();
        if (cycle == 0) {
            first_before = before;
        }
        spin_callbacks = 0;
        spin_min_receipt = 0;
        ros_spinOnce();
        check_split();
        out.header.seq = cycle;
        out.header.stamp.sec = ros_time_sec();
        out.header.stamp.nsec = ros_time_nsec();
        put_time(newest_receipt, 0);
        out.pose.covariance[2] = newest_seq;
        put_time(before, 3);
        put_time(init_time, 5);
        out.pose.covariance[7] = (double)callbacks;
        out.pose.covariance[8] = (double)spin_callbacks;
        put_time(spin_min_receipt, 9);
        out.pose.covariance[11] = (double)unstable;
        out.pose.covariance[12] = (double)backwards;
        put_time(first_before, 13);
        out.pose.covariance[15] = (double)split_errors;
        ros_publish_probe_out(&out);
        cycle++;
        ros_rate_sleep();
    }
    return 0;
}
