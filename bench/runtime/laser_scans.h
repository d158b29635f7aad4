/* laser_scans.h: the scans and the checksum shared by the two harnesses of
 * the laser guard's instruction count (bench/laserscan.py):
 * fake_ros_laser_guard.c (the generated glue's C ROS API) and
 * hw_harness_laser_guard.cpp (the hand-written node's callbacks), so that
 * both are fed the same scans and fold the same commands.
 *
 * Scan k (k = cycle % LASER_SCANS) has laser_scan_length(k) ranges: shorter
 * than the sector's 543 (0, 300, 542), exactly 543, exactly 1081 (three
 * times: the scanner's usual scan) and longer (1082, 1500, 2000), in a
 * fixed order (the scan guard's lengths with -DSCAN_GUARD_SCANS).  Ranges are multiples of 1/8 (exact in float); in the scans
 * with k % 3 == 1 one range of the front sector (538..542) is 0.25 m, an
 * obstacle.  The fake clock reads 1 s + 20 ms per cycle.
 *
 * The scan guard's harnesses (bench/scan_guard.py: the same files built
 * with -DHW_SCAN_GUARD / -DFAKE_SCAN_GUARD, and
 * fake_ros_scan_guard_wrapper.cpp) use the same scans and fold the /closest
 * Float32 too (laser_fold_closest).  In C++, laser_scan_messages() builds
 * the scans as roscpp messages. */
#ifndef BENCH_LASER_SCANS_H
#define BENCH_LASER_SCANS_H

#define LASER_SCANS 10
#define LASER_FRAME "laser"
#define LASER_FRAME_LEN 5

#include <stdlib.h>

#ifdef SCAN_GUARD_SCANS
/* The scan guard's (sector 480..600): empty, one range, the sector's edge
 * (600, 601), one short of the maximum, the maximum (three times), one
 * more, far more. */
static const unsigned laser_scan_lengths[LASER_SCANS] = {1081, 0, 1, 600, 1080, 1081, 601, 1082, 2000, 1081};
#else
static const unsigned laser_scan_lengths[LASER_SCANS] = {1081, 300, 543, 1081, 2000, 542, 1082, 0, 1081, 1500};
#endif

/* BENCH_SCAN_LENGTH (environment), if set, gives every scan that length. */
static inline unsigned laser_scan_length(long k)
{
    const char *s = getenv("BENCH_SCAN_LENGTH");
    if (s && *s)
        return (unsigned)atol(s);
    return laser_scan_lengths[k % LASER_SCANS];
}

static inline float laser_scan_range(long k, unsigned i)
{
    if (k % 3 == 1 && i == 538 + (unsigned)(k % 5))
        return 0.25f;
    return 1.25f + 0.125f * (float)((i * 3 + (unsigned)k) % 8);
}

static inline unsigned long long laser_clock_ns(long cycle)
{
    return 1000000000ULL + (unsigned long long)cycle * 20000000ULL;
}

/* Folds one published command into the checksum: every field the two nodes
 * set (the rest is checked to be zero through the sums too). */
static inline void laser_fold(double *checksum, unsigned seq, unsigned sec, unsigned nsec,
                              const unsigned char *frame, unsigned frame_len,
                              double lx, double ly, double lz, double ax, double ay, double az)
{
    unsigned i;
    double f = (double)frame_len * 1000.0;
    for (i = 0; i < frame_len; ++i)
        f += (double)frame[i] * (double)(i + 1);
    *checksum += lx * 3.0 + ly + lz + ax + ay + az + (double)seq + (double)sec * 1e-3 + (double)nsec * 1e-9 + f;
}

/* Folds one published /closest (the scan guard's std_msgs/Float32). */
static inline void laser_fold_closest(double *checksum, float closest)
{
    *checksum += (double)closest * 7.0;
}

/* The fields of scan p other than header and ranges (a C struct or a
 * roscpp message). */
#define LASER_SCAN_SET_FIELDS(p)           \
    do {                                   \
        (p)->angle_min = -2.35619449f;     \
        (p)->angle_max = 2.35619449f;      \
        (p)->angle_increment = 0.00436332313f; \
        (p)->scan_time = 0.025f;           \
        (p)->range_min = 0.1f;             \
        (p)->range_max = 30.0f;            \
    } while (0)

#ifdef __cplusplus
#include <boost/make_shared.hpp>
#include <geometry_msgs/TwistStamped.h>
#include <ros/time.h>
#include <sensor_msgs/LaserScan.h>
#include <string>
#include <vector>

/* Cycle `cycle`'s scan with its header.seq and header.stamp.sec set, the
 * simulated ROS time set to the cycle's (ros::Time::setNow) and written to
 * *now. */
static inline const sensor_msgs::LaserScan::Ptr &
laser_scan_of_cycle(const std::vector<sensor_msgs::LaserScan::Ptr> &scans, long cycle, ros::Time *now)
{
    const sensor_msgs::LaserScan::Ptr &m = scans[cycle % LASER_SCANS];
    now->fromNSec(laser_clock_ns(cycle));
    ros::Time::setNow(*now);
    m->header.seq = unsigned(cycle);
    m->header.stamp.sec = now->sec;
    return m;
}

/* laser_fold of a roscpp command. */
static inline void laser_fold_twist(double *checksum, const geometry_msgs::TwistStamped &c)
{
    const std::string &f = c.header.frame_id;
    laser_fold(checksum, c.header.seq, c.header.stamp.sec, c.header.stamp.nsec,
               reinterpret_cast<const unsigned char *>(f.data()), unsigned(f.size()), c.twist.linear.x,
               c.twist.linear.y, c.twist.linear.z, c.twist.angular.x, c.twist.angular.y, c.twist.angular.z);
}

/* The scans as roscpp messages (header.seq and header.stamp are set per
 * cycle by the harness). */
static inline std::vector<sensor_msgs::LaserScan::Ptr> laser_scan_messages()
{
    std::vector<sensor_msgs::LaserScan::Ptr> scans;
    for (long k = 0; k < LASER_SCANS; ++k) {
        sensor_msgs::LaserScan::Ptr m = boost::make_shared<sensor_msgs::LaserScan>();
        m->header.frame_id = LASER_FRAME;
        LASER_SCAN_SET_FIELDS(m);
        m->ranges.resize(laser_scan_length(k));
        for (unsigned i = 0; i < m->ranges.size(); ++i) m->ranges[i] = laser_scan_range(k, i);
        scans.push_back(m);
    }
    return scans;
}
#endif

#endif
