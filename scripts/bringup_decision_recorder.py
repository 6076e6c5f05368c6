#!/usr/bin/python3
"""Stands in for create_driver when recorded data is replayed (launch/replay.launch), and records
what the obstacle node decides.

- Serves the `drive_distance` action (sl_msgs/DriveDistance) like the driver: a new goal
  pre-empts the running one, a cancel ends it; progress is the distance base_link moved in the
  odometry frame (tf ~odom_frame -> ~base_frame, from the bag), so the obstacle node sees goals
  finish as they did on the robot. Without odometry in the bag, goals run until pre-empted.
- Subscribes `cmd_vel`, so the obstacle node finds a driver in either command mode.
- Logs every change of decision (state, reason, command) and, with ~output set, writes one CSV
  line per obstacle_status message.

- Starts the replay: replay.launch starts `rosbag play --pause` (its clock runs, so the nodelets
  load); once the decoder subscribes to the image topic (~wait_topic) the recorder resumes the
  player through its ~pause_service, so that no recorded frame is lost at the start.

Parameters: ~output (CSV path, empty: none), ~odom_frame (odom), ~base_frame (base_link),
~tolerance (m, goal reached this close to its distance, 0.002), ~pause_service (the player's
pause_playback service, empty: none), ~wait_topic (camera/image_raw), ~wait_timeout (s, 60).
"""

import math
import threading
import time

import actionlib
import rosgraph
import rospy
import tf2_ros
from geometry_msgs.msg import Twist
from sl_msgs.msg import DriveDistanceAction, DriveDistanceFeedback, DriveDistanceResult
from sl_msgs.msg import ObstacleStatus
from std_srvs.srv import SetBool

STATES = {0: "STALE", 1: "STOPPED", 2: "BLOCKED", 3: "TURNING", 4: "SLOWING", 5: "DRIVING"}
COMMANDS = {0: "NONE", 1: "STOP", 2: "DRIVE", 3: "TURN"}
REASONS = {getattr(ObstacleStatus, n): n[len("REASON_"):] for n in dir(ObstacleStatus) if n.startswith("REASON_")}
CSV_HEADER = ("time,cloud_stamp,state,reason,command,command_distance,command_speed,command_angular_speed,"
              "nearest_distance,free_distance,coverage,points_in_box,obstacle_points\n")


class DecisionRecorder:
    def __init__(self):
        self.odom_frame = rospy.get_param("~odom_frame", "odom")
        self.base_frame = rospy.get_param("~base_frame", "base_link")
        self.tolerance = float(rospy.get_param("~tolerance", 0.002))
        if not self.tolerance > 0.0:
            raise ValueError("~tolerance must be > 0 m")
        output = rospy.get_param("~output", "")
        self.csv = open(output, "w") if output else None
        if self.csv:
            self.csv.write(CSV_HEADER)
        self.lock = threading.Lock()
        self.last_key = None
        self.goals = 0
        self.turns = 0
        self.buffer = tf2_ros.Buffer(rospy.Duration(30.0))
        self.listener = tf2_ros.TransformListener(self.buffer)
        self.cmd_sub = rospy.Subscriber("cmd_vel", Twist, self.on_cmd_vel, queue_size=10)
        self.status_sub = rospy.Subscriber("obstacle_status", ObstacleStatus, self.on_status, queue_size=50)
        self.server = actionlib.SimpleActionServer("drive_distance", DriveDistanceAction, self.execute, False)
        self.server.start()
        rospy.loginfo("decision recorder: serving drive_distance (progress from tf %s -> %s)%s", self.odom_frame,
                      self.base_frame, ", writing %s" % output if output else "")

    def start_player(self, service, topic, timeout):
        """Resumes the paused player once `topic` has a subscriber (the decoder is ready)."""
        topic = rospy.resolve_name(topic)
        master = rosgraph.Master(rospy.get_name())
        deadline = time.monotonic() + timeout
        while not rospy.is_shutdown():
            try:
                _, subscribers, _ = master.getSystemState()
                if any(name == topic and nodes for name, nodes in subscribers):
                    break
            except (rosgraph.MasterError, OSError) as e:
                rospy.logwarn_throttle(5.0, "decision recorder: cannot ask the master: %s", e)
            if time.monotonic() > deadline:
                rospy.logwarn("decision recorder: nobody subscribes %s after %.0f s; starting the replay anyway",
                              topic, timeout)
                break
            time.sleep(0.2)
        try:
            rospy.wait_for_service(service, timeout=timeout)
            rospy.ServiceProxy(service, SetBool)(False)
            rospy.loginfo("decision recorder: %s has a subscriber, replay started", topic)
        except (rospy.ROSException, rospy.ServiceException) as e:
            rospy.logerr("decision recorder: cannot resume the player through %s: %s", service, e)

    def position(self):
        """(x, y) of base_frame in odom_frame now, or None."""
        try:
            t = self.buffer.lookup_transform(self.odom_frame, self.base_frame, rospy.Time(0))
        except (tf2_ros.LookupException, tf2_ros.ConnectivityException, tf2_ros.ExtrapolationException):
            return None
        return (t.transform.translation.x, t.transform.translation.y)

    def execute(self, goal):
        self.goals += 1
        rospy.loginfo("goal %d: %.3f m at %.3f m/s", self.goals, goal.distance, goal.speed)
        result = DriveDistanceResult()
        if not (math.isfinite(goal.distance) and math.isfinite(goal.speed)) or goal.speed <= 0.0:
            result.reason = DriveDistanceResult.INVALID_GOAL
            result.message = "invalid goal"
            self.server.set_aborted(result, result.message)
            return
        start = self.position()
        travelled = 0.0
        rate = rospy.Rate(20.0)
        while not rospy.is_shutdown():
            if self.server.is_preempt_requested():
                result.distance_travelled = math.copysign(travelled, goal.distance)
                result.reason = DriveDistanceResult.PREEMPTED
                self.server.set_preempted(result, "pre-empted")
                return
            here = self.position()
            if start is None:
                start = here
            elif here is not None:
                travelled = math.hypot(here[0] - start[0], here[1] - start[1])
            feedback = DriveDistanceFeedback()
            feedback.distance_travelled = math.copysign(travelled, goal.distance)
            feedback.distance_remaining = goal.distance - feedback.distance_travelled
            self.server.publish_feedback(feedback)
            if travelled >= abs(goal.distance) - self.tolerance:
                result.distance_travelled = feedback.distance_travelled
                result.reason = DriveDistanceResult.REACHED
                self.server.set_succeeded(result, "reached")
                return
            try:
                rate.sleep()
            except rospy.ROSInterruptException:
                break
        result.reason = DriveDistanceResult.DISCONNECTED
        self.server.set_aborted(result, "shutting down")

    def on_cmd_vel(self, msg):
        if msg.angular.z != 0.0 and msg.linear.x == 0.0:
            self.turns += 1

    def on_status(self, s):
        key = (s.state, s.reason_code, s.command)
        with self.lock:
            if key != self.last_key:
                self.last_key = key
                rospy.loginfo("decision: %s / %s, command %s: %s", STATES.get(s.state, s.state),
                              REASONS.get(s.reason_code, s.reason_code), COMMANDS.get(s.command, s.command), s.reason)
            if self.csv:
                self.csv.write("%.6f,%.6f,%s,%s,%s,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%d,%d\n" % (
                    s.header.stamp.to_sec(), s.cloud_stamp.to_sec(), STATES.get(s.state, s.state),
                    REASONS.get(s.reason_code, s.reason_code), COMMANDS.get(s.command, s.command), s.command_distance,
                    s.command_speed, s.command_angular_speed, s.nearest_distance, s.free_distance, s.coverage,
                    s.points_in_box, s.obstacle_points))
                self.csv.flush()

    def close(self):
        with self.lock:
            if self.csv:
                self.csv.close()
                self.csv = None


def main():
    rospy.init_node("decision_recorder")
    try:
        recorder = DecisionRecorder()
    except (ValueError, OSError) as e:
        rospy.logfatal("decision recorder: %s", e)
        raise SystemExit(1)
    rospy.on_shutdown(recorder.close)
    pause_service = rospy.get_param("~pause_service", "")
    if pause_service:
        starter = threading.Thread(target=recorder.start_player, daemon=True, args=(
            pause_service, rospy.get_param("~wait_topic", "camera/image_raw"),
            float(rospy.get_param("~wait_timeout", 60.0))))
        starter.start()
    rospy.spin()


if __name__ == "__main__":
    main()
