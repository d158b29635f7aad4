/* fake_rcl.h: what a node's driver provides to bench/runtime/fake_rcl.c
 * (fake_rcl_landshark.c, fake_rcl_scan_guard.c). */
#ifndef BENCH_FAKE_RCL_H
#define BENCH_FAKE_RCL_H

/* The driver's index of a topic (exit 3 if it does not know the topic). */
int bench_topic(const char *topic);
/* Cycle `cycle`'s message on subscription `topic` into the rosidl message
 * `msg` (of the topic's type, initialized by the node) and its reception
 * time into *rx; 0 if there is none this cycle. */
int bench_take(int topic, void *msg, long cycle, unsigned long long *rx);
/* A message the node published on `topic` during cycle `cycle`. */
void bench_published(int topic, const void *msg, long cycle);
/* At exit: prints the checksum of what was published, and `cycles`. */
void bench_report(long cycles);

/* The checksum of what was published (FNV-1a over 64-bit words): fold a
 * word, a double's bits; the checksum so far. */
void fake_rcl_fold(unsigned long long v);
void fake_rcl_fold_double(double x);
unsigned long long fake_rcl_checksum(void);
/* Fold a published TwistStamped's frame_id (its size, its bytes) and the 6
 * doubles of its twist (the stamp is the driver's to fold). */
struct geometry_msgs__msg__TwistStamped;
void fake_rcl_fold_frame_and_twist(const struct geometry_msgs__msg__TwistStamped *m);

/* The current cycle (the number of clock_nanosleep calls so far). */
long fake_rcl_cycle(void);

#endif
