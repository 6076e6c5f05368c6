#!/usr/bin/python3
"""The workstation's side of scripts/two_machines_test.sh, headless: subscribes to every topic that
rviz/sl.rviz's enabled displays show (with launch/view.launch's remappings, as rviz started by
view.launch subscribes them, plus /tf and /tf_static), waits until the map, the cloud and the status
arrive, measures the bytes per second they carry, then turns the robot in place through the safety
filter (cmd_vel_in) and checks that the simulated robot's true heading changed.

    two_machines_client.py [--rviz FILE] [--view FILE] [--link IFACE] [--max-rate MB/S] ...

Exit status 0 when everything arrived, the displayed topics carried at most --max-rate MB/s and the
robot turned; 1 with a line "FAILED: <what>".
Without a ROS master: ROS_MASTER_URI and ROS_IP as on any workstation.
"""

import argparse
import math
import os
import sys
import threading
import xml.etree.ElementTree as ET

import yaml

import rospy
from geometry_msgs.msg import PoseStamped, Twist

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REQUIRED = ("/local_map", "/points", "/obstacle_status")
TOPIC_KEYS = ("Topic", "Image Topic", "Marker Topic")


def rviz_topics(rviz_file):
    """Topics of the enabled displays of an rviz configuration (Map displays also *_updates)."""
    with open(rviz_file) as f:
        config = yaml.safe_load(f)
    topics = set()

    def walk(displays):
        for d in displays or []:
            if not d.get("Enabled", False):
                continue
            walk(d.get("Displays"))  # groups
            for key in TOPIC_KEYS:
                if isinstance(d.get(key), str) and d[key]:
                    topics.add(d[key])
                    if d.get("Class") == "rviz/Map":
                        topics.add(d[key] + "_updates")

    walk(config["Visualization Manager"]["Displays"])
    return topics


def view_remaps(view_file):
    """The <remap from to> of the rviz node in view.launch."""
    remaps = {}
    for node in ET.parse(view_file).getroot().iter("node"):
        if node.get("pkg") == "rviz":
            for r in node.iter("remap"):
                remaps[r.get("from")] = r.get("to")
    return remaps


class Counter:
    """Bytes and messages per topic, from the serialized messages (rospy.AnyMsg)."""

    def __init__(self, topics):
        self.lock = threading.Lock()
        self.bytes = {t: 0 for t in topics}
        self.count = {t: 0 for t in topics}
        self.last = {}
        self.subs = [rospy.Subscriber(t, rospy.AnyMsg, self.on_msg, t, queue_size=2) for t in topics]

    def on_msg(self, msg, topic):
        with self.lock:
            self.bytes[topic] += len(msg._buff) + 4  # TCPROS: 4-byte length before each message
            self.count[topic] += 1
            self.last[topic] = msg._buff

    def latest(self, topic, msg_class, timeout):
        """The newest message of @p topic deserialized as @p msg_class, after waiting for a new one."""
        _, count = self.snapshot()
        deadline = rospy.get_time() + timeout
        while not rospy.is_shutdown() and rospy.get_time() < deadline:
            with self.lock:
                if self.count[topic] > count[topic]:
                    return msg_class().deserialize(self.last[topic])
            rospy.sleep(0.05)
        fail("no message on %s within %.0f s" % (topic, timeout))

    def snapshot(self):
        with self.lock:
            return dict(self.bytes), dict(self.count)


def yaw_of(pose):
    q = pose.pose.orientation
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def fail(what):
    print("FAILED: " + what, flush=True)
    sys.exit(1)


def wait_required(counter, timeout):
    deadline = rospy.get_time() + timeout
    while not rospy.is_shutdown() and rospy.get_time() < deadline:
        _, count = counter.snapshot()
        if all(count[t] > 0 for t in REQUIRED):
            return
        rospy.sleep(0.2)
    _, count = counter.snapshot()
    fail("no message within %.0f s on %s" % (timeout, ", ".join(t for t in REQUIRED if count[t] == 0)))


def link_bytes(link):
    """Bytes the network interface @p link received (this namespace's sysfs); None without one."""
    if not link:
        return None
    with open("/sys/class/net/%s/statistics/rx_bytes" % link) as f:
        return int(f.read())


def measure(counter, seconds, link, max_rate):
    bytes0, count0 = counter.snapshot()
    link0 = link_bytes(link)
    t0 = rospy.get_time()
    rospy.sleep(seconds)
    bytes1, count1 = counter.snapshot()
    link1 = link_bytes(link)
    dt = rospy.get_time() - t0
    total = 0
    print("topic                            msg/s      kB/s")
    for t in sorted(bytes1):
        b = bytes1[t] - bytes0[t]
        total += b
        print("%-30s %7.1f %9.1f" % (t, (count1[t] - count0[t]) / dt, b / dt / 1e3))
    print("received %.3f MB/s in %.1f s over the view's topics" % (total / dt / 1e6, dt), flush=True)
    if link:
        print("the link (%s) carried %.3f MB/s to this side (TCPROS, XML-RPC, TCP/IP headers)"
              % (link, (link1 - link0) / dt / 1e6), flush=True)
    if total / dt / 1e6 > max_rate:
        fail("the view's topics carry %.3f MB/s, more than %.2f MB/s" % (total / dt / 1e6, max_rate))


def turn(counter, seconds, rate, min_turn):
    """Turns in place (left) through cmd_vel_in; fails when the true heading grew less than min_turn."""
    pub = rospy.Publisher("/cmd_vel_in", Twist, queue_size=1)
    deadline = rospy.get_time() + 10.0
    while pub.get_num_connections() == 0 and rospy.get_time() < deadline:
        rospy.sleep(0.1)  # the safety filter's subscription, over the link
    if pub.get_num_connections() == 0:
        fail("nobody on the robot subscribes /cmd_vel_in")
    before = counter.latest("/true_pose", PoseStamped, 10.0)
    cmd = Twist()
    cmd.angular.z = rate
    end = rospy.get_time() + seconds
    while not rospy.is_shutdown() and rospy.get_time() < end:
        pub.publish(cmd)
        rospy.sleep(0.1)
    pub.publish(Twist())  # stop at once rather than at the filter's input timeout
    rospy.sleep(0.5)
    after = counter.latest("/true_pose", PoseStamped, 10.0)
    change = yaw_of(after) - yaw_of(before)
    travelled = math.atan2(math.sin(change), math.cos(change))
    print("turned %.3f rad (true pose) after %.1f s of angular.z %.2f rad/s" % (travelled, seconds, rate),
          flush=True)
    if travelled < min_turn:
        fail("the robot turned %.3f rad, less than %.3f rad" % (travelled, min_turn))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--rviz", default=os.path.join(ROOT, "rviz", "sl.rviz"))
    parser.add_argument("--view", default=os.path.join(ROOT, "launch", "view.launch"))
    parser.add_argument("--wait", type=float, default=30.0, help="s for the first map, cloud, status")
    parser.add_argument("--measure", type=float, default=10.0, help="s of bandwidth measurement")
    parser.add_argument("--link", default="", help="network interface whose received bytes to print")
    parser.add_argument("--max-rate", type=float, default=1.5, help="most MB/s of the displayed topics")
    parser.add_argument("--turn-time", type=float, default=3.0, help="s of turning")
    parser.add_argument("--turn-rate", type=float, default=0.5, help="commanded angular.z, rad/s")
    parser.add_argument("--min-turn", type=float, default=0.95, help="least true heading change, rad")
    args = parser.parse_args(rospy.myargv()[1:])

    try:
        remaps = view_remaps(args.view)
        topics = {remaps.get(t, t) for t in rviz_topics(args.rviz)} | {"/tf", "/tf_static"}
    except (OSError, KeyError, ET.ParseError, yaml.YAMLError) as e:
        fail("cannot read the displays of %s / %s: %s" % (args.rviz, args.view, e))
    topics |= set(REQUIRED) | {"/true_pose"}  # the status: markers show it; the true pose: the check

    rospy.init_node("workstation_client", anonymous=True)
    print("master %s, this side %s" % (os.environ.get("ROS_MASTER_URI"), os.environ.get("ROS_IP")), flush=True)
    counter = Counter(sorted(topics))
    wait_required(counter, args.wait)
    if not rospy.has_param("/robot_description"):
        fail("no robot_description on the master (rviz's robot model)")
    print("map, cloud and status arrived", flush=True)
    measure(counter, args.measure, args.link, args.max_rate)
    turn(counter, args.turn_time, args.turn_rate, args.min_turn)
    print("PASSED", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
