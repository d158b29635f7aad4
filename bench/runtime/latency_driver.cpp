// latency_driver.cpp: measures the latency of LandShark nodes (or of laser
// guards), from the publication of a change of their inputs to the receipt
// of the first output that reflects it (bench/runtime.py, BENCHMARKS.md
// section 3; bench/laserscan.py, section 10).
//
// usage: latency_driver [--scenario landshark|laser] EDGES PERIOD_MS PREFIX...
//        latency_driver feed SECONDS RATE_HZ        (LandShark only)
// (ROS remappings as usual)
//
// Each PREFIX names one node whose topics were remapped under it
// (/landshark/gps_velocity:=PREFIX/landshark/gps_velocity, ...; "-" for
// no prefix).  The nodes run side by side and the edges alternate between
// them in a random order, so that all of them are measured under the same
// machine load.
//
// Scenario "landshark" (the default): a node runs the LandShark controller
// (examples/landshark/controller): with all three inputs at 0 m/s its
// command settles at the saturation 2.0 m/s; when the inputs jump to
// 2.0 m/s the median moves, the error changes sign, and the very next
// command is below 0.7 m/s.  So, for each edge: inputs at 0 until a command
// of 2.0 arrives (the rest state), a random wait in [0, PERIOD_MS) (so that
// edges fall at every phase of the node's period), then t0, the three
// inputs published back to back with the value 2.0, and the latency is the
// arrival time of the first command below 1.5 minus t0 (steady clock;
// arrival time taken in the subscriber's callback, which an AsyncSpinner
// thread runs; the subscription asks for TCP_NODELAY).
//
// Scenario "laser": a node runs the laser guard
// (examples/laser_guard/laser_guard.yaml: /scan, sensor_msgs/LaserScan, in;
// /cmd_vel out).  The rest state: 1081-range scans with an obstacle at
// 0.5 m in the front sector (ranges 538..542), command 0; the edge: a
// 1081-range scan with the sector clear (every range 3 m), and the latency
// is the arrival of the first command of at least 0.25 (the guard's 0.5 m/s).
// Prints one line "latency_us <node index> <value>" per edge, then
// "lost <node index> <n>" for edges without an answer within 1 s.
//
// "feed" mode publishes the three inputs (slowly varying values, no
// prefix) at RATE_HZ for SECONDS and prints "outputs <n>", the number of
// commands received: the load of the whole-node instruction count.

#include <ros/ros.h>
#include <geometry_msgs/TwistStamped.h>
#include <sensor_msgs/LaserScan.h>

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

bool g_laser = false;  // the scenario: "laser" (else "landshark")

// The laser scenario's two scans: the sector blocked at 0.5 m (rest), clear.
sensor_msgs::LaserScan make_scan(bool clear)
{
    sensor_msgs::LaserScan s;
    s.header.frame_id = "laser";
    s.angle_min = -2.35619449f;
    s.angle_max = 2.35619449f;
    s.angle_increment = 0.00436332313f;
    s.range_min = 0.1f;
    s.range_max = 30.0f;
    s.ranges.assign(1081, 3.0f);
    if (!clear)
        for (int i = 538; i <= 542; ++i) s.ranges[i] = 0.5f;
    return s;
}

// The command in the rest state, and a command reflecting the edge.
bool at_rest(double v) { return g_laser ? v <= 0.001 : v >= 1.999; }
bool reacted(double v) { return g_laser ? v >= 0.25 : v < 1.5; }

// One node under test: its input publishers, its output subscription and
// the state of the current edge (shared with the AsyncSpinner thread).
struct Target {
    std::string prefix;
    std::vector<ros::Publisher> pubs;
    ros::Subscriber sub;
    std::atomic<int64_t> t0_ns{0};          // time of the current edge, 0 when not armed
    std::atomic<int64_t> latency_ns{-1};    // result of the current edge
    std::atomic<int64_t> last_high_ns{0};   // arrival time of the last command at rest
    std::atomic<long> outputs{0};           // commands received
    int lost = 0;

    void on_output(const geometry_msgs::TwistStamped::ConstPtr &m)
    {
        const int64_t t = now_ns();
        const double v = m->twist.linear.x;
        outputs.fetch_add(1);
        if (at_rest(v)) last_high_ns.store(t);
        const int64_t t0 = t0_ns.load();
        if (t0 != 0 && reacted(v) && latency_ns.load() < 0) latency_ns.store(t - t0);
    }

    // LandShark: the three inputs with this value (0: rest, 2: the edge).
    // Laser: value 0 publishes the rest scan, anything else the clear one.
    void publish_all(double value)
    {
        if (g_laser) {
            static const sensor_msgs::LaserScan rest = make_scan(false), clear = make_scan(true);
            pubs[0].publish(value == 0.0 ? rest : clear);
            return;
        }
        geometry_msgs::TwistStamped m;
        m.twist.linear.x = value;
        for (auto &p : pubs) p.publish(m);
    }

    bool connected() const
    {
        for (auto &p : pubs)
            if (p.getNumSubscribers() == 0) return false;
        return sub.getNumPublishers() > 0;
    }
};

void setup(ros::NodeHandle &nh, Target &t)
{
    const std::string p = t.prefix == "-" ? "" : t.prefix;
    std::string out;
    if (g_laser) {
        t.pubs.push_back(nh.advertise<sensor_msgs::LaserScan>(p + "/scan", 10));
        out = p + "/cmd_vel";
    } else {
        t.pubs.push_back(nh.advertise<geometry_msgs::TwistStamped>(p + "/landshark/left_wheel_velocity", 10));
        t.pubs.push_back(nh.advertise<geometry_msgs::TwistStamped>(p + "/landshark/right_wheel_velocity", 10));
        t.pubs.push_back(nh.advertise<geometry_msgs::TwistStamped>(p + "/landshark/gps_velocity", 10));
        out = p + "/landshark_control/base_velocity";
    }
    boost::function<void(const geometry_msgs::TwistStamped::ConstPtr &)> cb =
        [&t](const geometry_msgs::TwistStamped::ConstPtr &m) { t.on_output(m); };
    t.sub = nh.subscribe<geometry_msgs::TwistStamped>(out, 100, cb, ros::VoidConstPtr(),
                                                      ros::TransportHints().tcpNoDelay());
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
    if (argc >= 3 && std::string(argv[1]) == "--scenario") {
        const std::string sc = argv[2];
        if (sc != "landshark" && sc != "laser") {
            std::fprintf(stderr, "latency_driver: unknown scenario %s\n", sc.c_str());
            return 2;
        }
        g_laser = sc == "laser";
        argv[2] = argv[0];
        argv += 2;
        argc -= 2;
    }
    const bool feed = argc >= 2 && std::string(argv[1]) == "feed";
    if ((feed && argc < 4) || (!feed && argc < 4)) {
        std::fprintf(stderr, "usage: latency_driver [--scenario landshark|laser] EDGES PERIOD_MS PREFIX...\n"
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
    // Settle: inputs at rest until every node's command is at rest.
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
            // inputs at rest; wait for a command at rest that arrived after that
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
