// latency_driver.cpp: measures the latency of a LandShark node, from the
// publication of a change of its inputs to the receipt of the first output
// that reflects it (bench/runtime.py, BENCHMARKS.md section 3).
//
// usage: latency_driver EDGES PERIOD_MS   (ROS remappings as usual)
//
// The node runs the LandShark controller (examples/landshark/controller):
// with all three inputs at 0 m/s its command settles at the saturation
// 2.0 m/s; when the inputs jump to 2.0 m/s the median moves, the error
// changes sign, and the very next command is below 0.7 m/s.  So, for each
// edge: inputs at 0 until a command of 2.0 arrives, a random wait in
// [0, PERIOD_MS) (so that edges fall at every phase of the node's period),
// then t0, the three inputs published back to back with the value 2.0, and
// the latency is the arrival time of the first command below 1.5 minus t0
// (steady clock; arrival time taken in the subscriber's callback, which an
// AsyncSpinner thread runs; the subscription asks for TCP_NODELAY).
// Prints one line "latency_us <value>" per edge, then "lost <n>" for edges
// without an answer within 1 s.

#include <ros/ros.h>
#include <geometry_msgs/TwistStamped.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <thread>

namespace {

using Clock = std::chrono::steady_clock;

std::atomic<int64_t> g_t0_ns(0);          // time of the current edge, 0 when not armed
std::atomic<int64_t> g_latency_ns(-1);    // result of the current edge
std::atomic<int64_t> g_last_high_ns(0);   // arrival time of the last command >= 1.999

int64_t now_ns()
{
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

void output_callback(const geometry_msgs::TwistStamped::ConstPtr &m)
{
    const int64_t t = now_ns();
    const double v = m->twist.linear.x;
    if (v >= 1.999) g_last_high_ns.store(t);
    const int64_t t0 = g_t0_ns.load();
    if (t0 != 0 && v < 1.5 && g_latency_ns.load() < 0) g_latency_ns.store(t - t0);
}

void publish_all(ros::Publisher *pubs, double value)
{
    geometry_msgs::TwistStamped m;
    m.twist.linear.x = value;
    for (int i = 0; i < 3; ++i) pubs[i].publish(m);
}

bool wait_for(const std::function<bool()> &cond, double seconds)
{
    const int64_t deadline = now_ns() + int64_t(seconds * 1e9);
    while (ros::ok() && now_ns() < deadline) {
        if (cond()) return true;
        std::this_thread::sleep_for(std::chrono::microseconds(20));
    }
    return cond();
}

}  // namespace

int main(int argc, char **argv)
{
    ros::init(argc, argv, "latency_driver", ros::init_options::AnonymousName);
    if (argc < 3) {
        std::fprintf(stderr, "usage: latency_driver EDGES PERIOD_MS\n");
        return 2;
    }
    const int edges = std::atoi(argv[1]);
    const double period_ms = std::atof(argv[2]);
    ros::NodeHandle nh;
    ros::Publisher pubs[3] = {
        nh.advertise<geometry_msgs::TwistStamped>("/landshark/left_wheel_velocity", 10),
        nh.advertise<geometry_msgs::TwistStamped>("/landshark/right_wheel_velocity", 10),
        nh.advertise<geometry_msgs::TwistStamped>("/landshark/gps_velocity", 10),
    };
    ros::Subscriber sub = nh.subscribe("/landshark_control/base_velocity", 100, output_callback,
                                       ros::TransportHints().tcpNoDelay());
    ros::AsyncSpinner spinner(1);
    spinner.start();

    // Wait for the node: connected both ways.
    if (!wait_for([&] {
            return pubs[0].getNumSubscribers() > 0 && pubs[1].getNumSubscribers() > 0
                   && pubs[2].getNumSubscribers() > 0 && sub.getNumPublishers() > 0;
        }, 30.0)) {
        std::fprintf(stderr, "latency_driver: the node did not connect\n");
        return 1;
    }
    // Settle: inputs at 0 until the command saturates.
    const int64_t settle_start = now_ns();
    while (ros::ok() && now_ns() - settle_start < int64_t(3e9)) {
        publish_all(pubs, 0.0);
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        if (now_ns() - settle_start > int64_t(0.5e9) && g_last_high_ns.load() > settle_start + int64_t(0.3e9)) break;
    }
    std::mt19937 rng(12345);
    std::uniform_real_distribution<double> phase(0.0, period_ms * 1e6);
    int lost = 0;
    for (int e = 0; e < edges && ros::ok(); ++e) {
        // inputs low; wait for a saturated command that arrived after that
        publish_all(pubs, 0.0);
        const int64_t low_at = now_ns();
        if (!wait_for([&] { return g_last_high_ns.load() > low_at; }, 1.0)) {
            ++lost;
            continue;
        }
        const int64_t until = now_ns() + int64_t(phase(rng));
        while (now_ns() < until) { /* spin: sleeping would add its own jitter */ }
        g_latency_ns.store(-1);
        const int64_t t0 = now_ns();
        g_t0_ns.store(t0);
        publish_all(pubs, 2.0);
        if (wait_for([&] { return g_latency_ns.load() >= 0; }, 1.0)) {
            std::printf("latency_us %.3f\n", double(g_latency_ns.load()) / 1e3);
        } else {
            ++lost;
        }
        g_t0_ns.store(0);
    }
    publish_all(pubs, 0.0);
    std::printf("lost %d\n", lost);
    std::fflush(stdout);
    spinner.stop();
    return 0;
}
