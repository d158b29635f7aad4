"""The private master fixture itself: it answers, and leaves nothing behind."""

import os
import subprocess
import xmlrpc.client

from pyrosgen.ros.rosmaster import ros_master


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    # a zombie is not alive
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split()[2] != "Z"
    except FileNotFoundError:
        return False


def test_master_answers_and_is_stopped(tmp_path):
    with ros_master(tmp_path) as env:
        code, _msg, uri = xmlrpc.client.ServerProxy(env.uri).getUri("/test")
        assert code == 1 and str(env.port) in uri
        pid = env.proc.pid
        child = env.spawn(["sleep", "60"])
    assert not _alive(pid)
    assert not _alive(child.pid)


def test_processes_stopped_when_block_raises(tmp_path):
    pids = []
    try:
        with ros_master(tmp_path) as env:
            pids.append(env.proc.pid)
            pids.append(env.spawn(["sleep", "60"]).pid)
            raise RuntimeError("test failure")
    except RuntimeError:
        pass
    assert pids and not any(_alive(p) for p in pids)


def test_master_restart_same_port(tmp_path):
    with ros_master(tmp_path) as env:
        port = env.port
        env.stop_master()
        env.start_master()
        code, _msg, _uri = xmlrpc.client.ServerProxy(env.uri).getUri("/test")
        assert code == 1 and env.port == port


def test_rospy_round_trip(ros):
    """A rospy publisher and subscriber talk through the private master
    (Debian's rospy, run with Debian's interpreter)."""
    script = r'''
import rospy, sys
from std_msgs.msg import Float64
rospy.init_node("rt", anonymous=True)
got = []
rospy.Subscriber("/x", Float64, lambda m: got.append(m.data))
pub = rospy.Publisher("/x", Float64, queue_size=10)
import time
deadline = time.time() + 10
while not got and time.time() < deadline:
    pub.publish(Float64(2.5)); rospy.sleep(0.1)
print(got[0] if got else "none")
'''
    r = subprocess.run(["/usr/bin/python3", "-c", script], env=ros.env,
                       capture_output=True, text=True, timeout=60)
    assert r.stdout.strip() == "2.5", r.stderr
