// latency_driver.cpp: measures the latency of LandShark nodes, from the
// publication of a change of their inputs to the receipt of the first
// output that reflects it (bench/runtime.py, BENCHMARKS.md section 3).
//
// usage: latency_driver EDGES PERIOD_MS PREFIX...   (ROS remappings as usual)
//        latency_driver feed SECONDS RATE_HZ
//
// Each PREFIX names one node whose topics were remapped under it
// (/landshark/gps_velocity:=PREFIX/landshark/gps_velocity, ...; "-" for
// no prefix).  The nodes run side by side and the edges alternate between
// them in a random order, so that all of them are measured under the same
// machine load.
//
// A node runs the LandShark controller (examples/landshark/controller):
// with all three inputs at 0 m/s its command settles at the saturation
// 2.0 m/s; when the inputs jump to 2.0 m/s the median moves, the error
// changes sign, and the very next command is below 0.7 m/s.  So, for each
// edge: inputs at 0 until a command of 2.0 arrives, a random wait in
// [0, PERIOD_MS) (so that edges fall at every phase of the node's period),
// then t0, the three inputs published back to back with the value 2.0, and
// the latency is the arrival time of the first command below 1.5 minus t0
// (steady clock; arrival time taken in the subscriber's callback, which an
// AsyncSpinner thread runs; the subscription asks for TCP_NODELAY).
// Prints one line "latency_us <node index> <value>" per edge, then
// "lost <node index> <n>" for edges without an answer within 1 s.
//
// "feed" mode publishes the three inputs (slowly varying values, no
// prefix) at RATE_HZ for SECONDS and prints "outputs <n>", the number of
// commands received: the load of the whole-node instruction count.

#include <ros/ros.h>
#include <geometry_msgs/TwistStamped.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <functional>
#include <memory>
#include <vector>
#include <random>
#include <string>
#include <thread>

namespace {

using Clock = std::chrono::steady_clock;

int64_t now_ns()
{
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

// One node under test: its input publishers, its output subscription and
// the state of the current edge (shared with the AsyncSpinner thread).
struct Target {
    std::string prefix;
    ros::Publisher pubs[3];
    ros::Subscriber sub;
    std::atomic<int64_t> t0_ns{0};          // time of the current edge, 0 when not armed
    std::atomic<int64_t> latency_ns{-1};    // result of the current edge
    std::atomic<int64_t> last_high_ns{0};   // arrival time of the last command >= 1.999
    std::atomic<long> outputs{0};           // commands received
    int lost = 0;

    void on_output(const geometry_msgs::TwistStamped::ConstPtr &m)
    {
        const int64_t t = now_ns();
        const double v = m->twist.linear.x;
        outputs.fetch_add(1);
        if (v >= 1.999) last_high_ns.store(t);
        const int64_t t0 = t0_ns.load();
        if (t0 != 0 && v < 1.5 && latency_ns.load() < 0) latency_ns.store(t - t0);
    }

    void publish_all(double value)
    {
        geometry_msgs::TwistStamped m;
        m.twist.linear.x = value;
        for (int i = 0; i < 3; ++i) pubs[i].publish(m);
    }

    bool connected() const
    {
        return pubs[0].getNumSubscribers() > 0 && pubs[1].getNumSubscribers() > 0
               && pubs[2].getNumSubscribers() > 0 && sub.getNumPublishers() > 0;
    }
};

void setup(ros::NodeHandle &nh, Target &t)
{
    const std::string p = t.prefix == "-" ? "" : t.prefix;
    t.pubs[0] = nh.advertise<geometry_msgs::TwistStamped>(p + "/landshark/left_wheel_velocity", 10);
    t.pubs[1] = nh.advertise<geometry_msgs::TwistStamped>(p + "/landshark/right_wheel_velocity", 10);
    t.pubs[2] = nh.advertise<geometry_msgs::TwistStamped>(p + "/landshark/gps_velocity", 10);
    boost::function<void(const geometry_msgs::TwistStamped::ConstPtr &)> cb =
        [&t](const geometry_msgs::TwistStamped::ConstPtr &m) { t.on_output(m); };
    t.sub = nh.subscribe<geometry_msgs::TwistStamped>(p + "/landshark_control/base_velocity", 100, cb,
                                                      ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
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
    const bool feed = argc >= 2 && std::string(argv[1]) == "feed";
    if ((feed && argc < 4) || (!feed && argc < 4)) {
        std::fprintf(stderr, "usage: latency_driver EDGES PERIOD_MS PREFIX...\n"
                             "       latency_driver feed SECONDS RATE_HZ\n");
        return 2;
    }
    ros::NodeHandle nh;
    std::vector<std::unique_ptr<Target>> targets;
    if (feed) {
        targets.emplace_back(new Target);
        targets.back()->prefix = "-";
    } else {
        for (int i = 3; i < argc; ++i) {
            targets.emplace_back(new Target);
            targets.back()->prefix = argv[i];
        }
    }
    for (auto &t : targets) setup(nh, *t);
    ros::AsyncSpinner spinner(1);
    spinner.start();

    // Wait for the nodes: connected both ways.
    if (!wait_for([&] {
            for (auto &t : targets)
                if (!t->connected()) return false;
            return true;
        }, 30.0)) {
        std::fprintf(stderr, "latency_driver: a node did not connect\n");
        return 1;
    }
    if (feed) {
        const double seconds = std::atof(argv[2]);
        ros::Rate rate(std::atof(argv[3]));
        const int64_t start = now_ns();
        long k = 0;
        while (ros::ok() && now_ns() - start < int64_t(seconds * 1e9)) {
            targets[0]->publish_all(0.5 + 0.01 * double(k++ % 100));
            rate.sleep();
        }
        std::printf("outputs %ld\n", targets[0]->outputs.load());
        std::fflush(stdout);
        spinner.stop();
        return 0;
    }
    const int edges = std::atoi(argv[1]);
    const double period_ms = std::atof(argv[2]);
    // Settle: inputs at 0 until every command saturates.
    const int64_t settle_start = now_ns();
    while (ros::ok() && now_ns() - settle_start < int64_t(5e9)) {
        for (auto &t : targets) t->publish_all(0.0);
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        bool all = now_ns() - settle_start > int64_t(0.5e9);
        for (auto &t : targets) all = all && t->last_high_ns.load() > settle_start + int64_t(0.3e9);
        if (all) break;
    }
    std::mt19937 rng(12345);
    std::uniform_real_distribution<double> phase(0.0, period_ms * 1e6);
    std::vector<std::size_t> order(targets.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    for (int e = 0; e < edges && ros::ok(); ++e) {
        std::shuffle(order.begin(), order.end(), rng);
        for (std::size_t i : order) {
            Target &t = *targets[i];
            // inputs low; wait for a saturated command that arrived after that
            t.publish_all(0.0);
            const int64_t low_at = now_ns();
            if (!wait_for([&] { return t.last_high_ns.load() > low_at; }, 1.0)) {
                ++t.lost;
                continue;
            }
            const int64_t until = now_ns() + int64_t(phase(rng));
            while (now_ns() < until) { /* spin: sleeping would add its own jitter */ }
            t.latency_ns.store(-1);
            t.t0_ns.store(now_ns());
            t.publish_all(2.0);
            if (wait_for([&] { return t.latency_ns.load() >= 0; }, 1.0)) {
                std::printf("latency_us %zu %.3f\n", i, double(t.latency_ns.load()) / 1e3);
            } else {
                ++t.lost;
            }
            t.t0_ns.store(0);
            t.publish_all(0.0);
        }
    }
    for (std::size_t i = 0; i < targets.size(); ++i) std::printf("lost %zu %d\n", i, targets[i]->lost);
    std::fflush(stdout);
    spinner.stop();
    return 0;
}
