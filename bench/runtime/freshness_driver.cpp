// freshness_driver.cpp: measures how long the velocity guard
// (examples/velocity_guard) takes to notice that a command source went
// silent: from the publication of the last teleop command to the receipt of
// the first /cmd_vel that no longer follows it (bench/freshness.py,
// BENCHMARKS.md).
//
// usage: freshness_driver TRIALS PERIOD_MS [SEED [QUIET_MS]]   (ROS remappings as usual)
//
// Both sources publish at the node's rate (1000 / PERIOD_MS Hz): teleop
// linear.x = 1.0, nav linear.x = 2.0.  Each trial: teleop and nav on until
// the node's commands follow teleop (1.0) again; then a random wait in
// [0, PERIOD_MS) (so that the last message falls at every phase of the
// node's cycle), t0, the last teleop command; nav goes on.  The latency is
// the arrival time of the first command other than 1.0, minus t0 (steady
// clock; arrival time taken in the subscriber's callback, which an
// AsyncSpinner thread runs; the subscription asks for TCP_NODELAY).
// QUIET_MS (default 0): the last teleop command comes at least that long
// after the one before it.  The node's subscriptions do not ask for
// TCP_NODELAY, so Nagle's algorithm could hold a message back behind an
// unacknowledged one (Linux delays an ACK by up to 40 ms); 60 ms rules that
// out.  Measured on loopback: the same latencies with 0 and 60.
// Prints "latency_us <trial> <value> <command>" per trial ("<command>" the
// linear.x of that first other command: 2.0, nav's), then "lost <n>"
// (trials without an answer within 2 s) and "commands <n>".

#include <ros/ros.h>
#include <geometry_msgs/Twist.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <mutex>
#include <random>
#include <string>
#include <thread>

namespace {

using Clock = std::chrono::steady_clock;

int64_t now_ns()
{
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

const double TELEOP = 1.0;
const double NAV = 2.0;

std::atomic<int64_t> g_t0{0};            // publication of the last teleop command; 0: not armed
std::atomic<int64_t> g_latency{-1};      // result of the current trial
std::atomic<int64_t> g_last_teleop_out{0};  // arrival of the last command equal to TELEOP
std::atomic<long> g_commands{0};
std::mutex g_value_mutex;
double g_value = 0.0;                    // the first other command of the current trial

void on_command(const geometry_msgs::Twist::ConstPtr &m)
{
    const int64_t t = now_ns();
    const double v = m->linear.x;
    g_commands.fetch_add(1);
    if (v == TELEOP) {
        g_last_teleop_out.store(t);
        return;
    }
    const int64_t t0 = g_t0.load();
    if (t0 != 0 && g_latency.load() < 0) {
        {
            std::lock_guard<std::mutex> lock(g_value_mutex);
            g_value = v;
        }
        g_latency.store(t - t0);
    }
}

// The sources, each at its own schedule.
struct Sources {
    ros::Publisher teleop, nav;
    int64_t period_ns = 20000000;
    int64_t next_nav = 0, next_teleop = 0;
    bool teleop_on = true;
    int64_t last_teleop = 0;

    void send(ros::Publisher &p, double v)
    {
        geometry_msgs::Twist m;
        m.linear.x = v;
        m.angular.z = v / 10.0;
        p.publish(m);
    }

    // Publish what is due; sleep a little.
    void tick()
    {
        const int64_t t = now_ns();
        if (t >= next_nav) {
            send(nav, NAV);
            next_nav += period_ns;
            if (next_nav < t) next_nav = t + period_ns;
        }
        if (teleop_on && t >= next_teleop) {
            send(teleop, TELEOP);
            last_teleop = now_ns();
            next_teleop += period_ns;
            if (next_teleop < t) next_teleop = t + period_ns;
        }
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }

    // Run the schedule until cond() or the deadline.
    bool run_until(const std::function<bool()> &cond, double seconds)
    {
        const int64_t deadline = now_ns() + int64_t(seconds * 1e9);
        while (ros::ok() && now_ns() < deadline) {
            if (cond()) return true;
            tick();
        }
        return cond();
    }
};

}  // namespace

int main(int argc, char **argv)
{
    ros::init(argc, argv, "freshness_driver", ros::init_options::AnonymousName);
    if (argc < 3) {
        std::fprintf(stderr, "usage: freshness_driver TRIALS PERIOD_MS [SEED [QUIET_MS]]\n");
        return 2;
    }
    const int trials = std::atoi(argv[1]);
    const double period_ms = std::atof(argv[2]);
    const unsigned seed = argc > 3 ? unsigned(std::atoi(argv[3])) : 12345u;
    const double quiet_ms = argc > 4 ? std::atof(argv[4]) : 0.0;
    ros::NodeHandle nh;
    Sources src;
    src.period_ns = int64_t(period_ms * 1e6);
    src.teleop = nh.advertise<geometry_msgs::Twist>("/teleop/cmd_vel", 10);
    src.nav = nh.advertise<geometry_msgs::Twist>("/nav/cmd_vel", 10);
    boost::function<void(const geometry_msgs::Twist::ConstPtr &)> cb = on_command;
    ros::Subscriber sub = nh.subscribe<geometry_msgs::Twist>("/cmd_vel", 100, cb, ros::VoidConstPtr(),
                                                             ros::TransportHints().tcpNoDelay());
    ros::AsyncSpinner spinner(1);
    spinner.start();
    const int64_t start = now_ns();
    while (ros::ok() && !(src.teleop.getNumSubscribers() > 0 && src.nav.getNumSubscribers() > 0
                          && sub.getNumPublishers() > 0)) {
        if (now_ns() - start > int64_t(30e9)) {
            std::fprintf(stderr, "freshness_driver: the node did not connect\n");
            return 1;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    src.next_nav = src.next_teleop = now_ns();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> phase(0.0, period_ms * 1e6);
    int lost = 0;
    for (int k = 0; k < trials && ros::ok(); ++k) {
        // both sources on until the commands follow teleop again (three
        // commands' worth after the first)
        src.teleop_on = true;
        const int64_t resumed = now_ns();
        if (!src.run_until([&] { return g_last_teleop_out.load() > resumed + 3 * src.period_ns; }, 3.0)) {
            ++lost;
            continue;
        }
        // the last teleop command: at least QUIET_MS after the one before
        // it (Nagle), at a random phase of the node's cycle
        src.teleop_on = false;
        const int64_t quiet = src.last_teleop + int64_t(quiet_ms * 1e6);
        src.run_until([&] { return now_ns() >= quiet; }, 1.0);
        const int64_t until = now_ns() + int64_t(phase(rng));
        src.run_until([&] { return now_ns() >= until; }, 1.0);
        // (the commands still follow teleop: QUIET_MS + PERIOD_MS < 500 ms)
        g_latency.store(-1);
        g_t0.store(now_ns());
        src.send(src.teleop, TELEOP);
        src.last_teleop = now_ns();
        if (src.run_until([&] { return g_latency.load() >= 0; }, 2.0)) {
            double v;
            {
                std::lock_guard<std::mutex> lock(g_value_mutex);
                v = g_value;
            }
            std::printf("latency_us %d %.3f %.17g\n", k, double(g_latency.load()) / 1e3, v);
            std::fflush(stdout);
        } else {
            ++lost;
        }
        g_t0.store(0);
        src.next_teleop = now_ns();
    }
    std::printf("lost %d\ncommands %ld\n", lost, g_commands.load());
    std::fflush(stdout);
    spinner.stop();
    return 0;
}
