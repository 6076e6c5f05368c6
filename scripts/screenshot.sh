#!/usr/bin/env bash
# Screenshot of rviz (rviz/sl.rviz) during a simulation run, made headless under Xvfb:
#
#   scripts/screenshot.sh [OUTPUT.png] [WORKSPACE] [-- sim.launch arguments...]
#
# Starts Xvfb on a free display, runs `roslaunch sl_bringup sim.launch rviz:=true` (the room scene
# unless arguments say otherwise) on its own ROS master port, waits until the robot has stopped
# before an obstacle (obstacle_status BLOCKED / OBSTACLE, at most 120 s) and two seconds more, grabs
# the screen (xwd), writes OUTPUT (default doc/sl_rviz.png, 256 colours when that keeps it under
# 300 KB) and stops everything it started. Needs xvfb, x11-apps (xwd) and imagemagick (convert).
# With GOAL="x y" (world frame, m) and `-- behaviour:=navigate ...` it sends that goal as rviz's
# "2D Nav Goal" does and grabs the screen once the robot has driven GOAL_TRAVEL m (default 1.0)
# toward it, with the plan in view. With WAIT=<s> (e.g. with `-- behaviour:=cover`, the coverage
# layer filling) it grabs the screen WAIT seconds after the launch instead.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$root/doc/sl_rviz.png"
ws="$root/catkin_ws"
[[ $# -gt 0 && $1 != "--" ]] && { out="$1"; shift; }
[[ $# -gt 0 && $1 != "--" ]] && { ws="$1"; shift; }
[[ $# -gt 0 && $1 == "--" ]] && shift
sim_args=("$@")
convert=/usr/bin/convert   # not a stand-in that may come first on PATH
for tool in Xvfb xwd "$convert"; do
  command -v "$tool" > /dev/null || { echo "screenshot: $tool missing (apt-get install xvfb x11-apps imagemagick)"; exit 1; }
done

export PATH=/usr/bin:/bin:$PATH PYTHONNOUSERSITE=1
unset PYTHONPATH PYTHONHOME
set +u
# shellcheck disable=SC1091
source "$ws/devel/setup.bash"
set -u
export ROS_MASTER_URI=http://localhost:11811
display=99
while [[ -e /tmp/.X11-unix/X$display || -e /tmp/.X$display-lock ]]; do display=$((display + 1)); done
export DISPLAY=:$display
export LIBGL_ALWAYS_SOFTWARE=1
work="$(mktemp -d)"
xvfb_pid=""
launch_pid=""

stop() {
  local pid=$1
  [[ -z $pid ]] && return
  kill -INT "$pid" 2> /dev/null || true
  for _ in $(seq 40); do kill -0 "$pid" 2> /dev/null || return 0; sleep 0.5; done
  kill -KILL "$pid" 2> /dev/null || true
}
cleanup() {
  stop "$launch_pid"
  stop "$xvfb_pid"
  rm -rf "$work"
}
trap cleanup EXIT

Xvfb "$DISPLAY" -screen 0 1400x900x24 -nolisten tcp > "$work/xvfb.log" 2>&1 &
xvfb_pid=$!
sleep 2
roslaunch -p 11811 sl_bringup sim.launch rviz:=true "${sim_args[@]}" > "$work/launch.log" 2>&1 &
launch_pid=$!

if [[ -n ${GOAL:-} ]]; then
  GOAL="$GOAL" GOAL_TRAVEL="${GOAL_TRAVEL:-1.0}" /usr/bin/python3 - <<'EOF' || { tail -n 30 "$work/launch.log"; exit 1; }
import os, sys, rospy
from geometry_msgs.msg import PoseStamped
from sl_msgs.msg import NavigationStatus
rospy.init_node("screenshot_goal", anonymous=True, disable_signals=True)
rospy.wait_for_message("/navigation_status", NavigationStatus, timeout=120.0)
pub = rospy.Publisher("/move_base_simple/goal", PoseStamped, queue_size=1, latch=True)
goal = PoseStamped()
goal.header.frame_id = "world"
goal.pose.position.x, goal.pose.position.y = (float(v) for v in os.environ["GOAL"].split())
rospy.sleep(1.0)
pub.publish(goal)
travel = float(os.environ["GOAL_TRAVEL"])
deadline = rospy.get_time() + 180.0
while rospy.get_time() < deadline:
    s = rospy.wait_for_message("/navigation_status", NavigationStatus, timeout=10.0)
    if s.travelled >= travel or s.state == NavigationStatus.SUCCEEDED:
        sys.exit(0)
    if s.state == NavigationStatus.ABORTED:
        sys.exit("screenshot: the goal was aborted: " + s.reason)
sys.exit("screenshot: the robot did not drive %.1f m toward the goal within 180 s" % travel)
EOF
elif [[ -n ${WAIT:-} ]]; then
  sleep "$WAIT"
else
/usr/bin/python3 - <<'EOF' || { tail -n 30 "$work/launch.log"; exit 1; }
import sys, rospy
from sl_msgs.msg import ObstacleStatus
rospy.init_node("screenshot_wait", anonymous=True, disable_signals=True)
deadline = rospy.get_time() + 120.0
while rospy.get_time() < deadline:
    try:
        s = rospy.wait_for_message("/obstacle_status", ObstacleStatus, timeout=5.0)
    except rospy.ROSException:
        continue
    if s.state == ObstacleStatus.BLOCKED and s.reason_code == ObstacleStatus.REASON_OBSTACLE:
        sys.exit(0)
sys.exit("screenshot: the robot did not stop before an obstacle within 120 s")
EOF
fi
sleep 2
xwd -root -silent > "$work/screen.xwd"
mkdir -p "$(dirname "$out")"
"$convert" "xwd:$work/screen.xwd" -strip "png:$out"
if [[ $(stat -c %s "$out") -gt 300000 ]]; then
  "$convert" "xwd:$work/screen.xwd" -strip -dither None -colors 256 "png8:$out"
fi
echo "screenshot: $out ($(stat -c %s "$out") bytes)"
