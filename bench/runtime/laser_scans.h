/* laser_scans.h: the scans and the checksum shared by the two harnesses of
 * the laser guard's instruction count (bench/laserscan.py):
 * fake_ros_laser_guard.c (the generated glue's C ROS API) and
 * hw_harness_laser_guard.cpp (the hand-written node's callbacks), so that
 * both are fed the same scans and fold the same commands.
 *
 * Scan k (k = cycle % LASER_SCANS) has laser_scan_length(k) ranges: shorter
 * than the sector's 543 (0, 300, 542), exactly 543, exactly 1081 (three
 * times: the scanner's usual scan) and longer (1082, 1500, 2000), in a
 * fixed order.  Ranges are multiples of 1/8 (exact in float); in the scans
 * with k % 3 == 1 one range of the front sector (538..542) is 0.25 m, an
 * obstacle.  The fake clock reads 1 s + 20 ms per cycle. */
#ifndef BENCH_LASER_SCANS_H
#define BENCH_LASER_SCANS_H

#define LASER_SCANS 10
#define LASER_FRAME "laser"
#define LASER_FRAME_LEN 5

static const unsigned laser_scan_lengths[LASER_SCANS] = {1081, 300, 543, 1081, 2000, 542, 1082, 0, 1081, 1500};

static inline unsigned laser_scan_length(long k)
{
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

#endif
