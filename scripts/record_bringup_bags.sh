#!/usr/bin/env bash
# Records the regression bags of the system tests from the simulator and writes their expectations.
#
#   scripts/record_bringup_bags.sh [WORKSPACE]      (default: catkin_ws, built with `make build`)
#
# For each bag: runs sim.launch on its scene (camera at 5 Hz, noise-free images so that the bag
# compresses to about 120 KB a frame), starts `rosbag record --bz2` of /camera/image_raw,
# /camera/camera_info and /tf at a start condition on the obstacle node's status (the wall inside
# the working volume; the first drive toward the leg), stops one second after the robot has
# stopped BLOCKED before the obstacle, then
# replays the bag through test/bag_<name>.test with write:= to store test/expectations/<name>.yaml.
# Re-run it when the decoder or the obstacle node changes on purpose, and commit bags and
# expectations together. Uses its own ROS master port (11711); stops only what it started.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ws="${1:-$root/catkin_ws}"
export PATH=/usr/bin:/bin:$PATH PYTHONNOUSERSITE=1
unset PYTHONPATH PYTHONHOME
set +u
# shellcheck disable=SC1091
source "$ws/devel/setup.bash"
set -u
port=11711
export ROS_MASTER_URI=http://localhost:$port
work="$(mktemp -d)"
launch_pid=""
record_pid=""

cleanup() {
  for pid in $record_pid $launch_pid; do
    kill -INT "$pid" 2>/dev/null || true
  done
  for pid in $record_pid $launch_pid; do
    for _ in $(seq 30); do kill -0 "$pid" 2>/dev/null || break; sleep 0.5; done
    kill -KILL "$pid" 2>/dev/null || true
  done
  record_pid=""
  launch_pid=""
}
trap 'cleanup; rm -rf "$work"' EXIT

# wait_for CONDITION TIMEOUT: returns when the obstacle node's status satisfies CONDITION (python
# expression on `s`, an sl_msgs/ObstacleStatus), fails after TIMEOUT s.
wait_for() {
  /usr/bin/python3 - "$1" "$2" <<'EOF'
import sys, rospy
from sl_msgs.msg import ObstacleStatus
condition, timeout = sys.argv[1], float(sys.argv[2])
rospy.init_node("record_bringup_wait", anonymous=True, disable_signals=True)
deadline = rospy.get_time() + timeout
while not rospy.is_shutdown() and rospy.get_time() < deadline:
    try:
        s = rospy.wait_for_message("/obstacle_status", ObstacleStatus, timeout=5.0)
    except rospy.ROSException:
        continue
    if eval(condition, {"ObstacleStatus": ObstacleStatus}, {"s": s}):
        sys.exit(0)
sys.exit("timed out waiting for: " + condition)
EOF
}

# record NAME SCENE START_CONDITION
record() {
  local name="$1" scene="$2" start="$3"
  echo "== $name: $scene"
  setsid roslaunch -p $port sl_bringup sim.launch scene:="$scene" rate:=5 noise:=false \
    > "$work/$name.launch.log" 2>&1 &
  launch_pid=$!
  wait_for "$start" 120
  rosbag record --bz2 -O "$work/$name.bag" /camera/image_raw /camera/camera_info /tf > "$work/$name.record.log" 2>&1 &
  record_pid=$!
  wait_for "s.state == ObstacleStatus.BLOCKED and s.reason_code == ObstacleStatus.REASON_OBSTACLE" 120
  sleep 1.0
  cleanup
  mkdir -p "$root/test/bags" "$root/test/expectations"
  mv "$work/$name.bag" "$root/test/bags/$name.bag"
  rosbag info "$root/test/bags/$name.bag" | grep -E '^(duration|size|topics| )'
  unset ROS_MASTER_URI
  # rostest needs the package named: its test files are reached through the package's test link.
  local pkg_dir
  pkg_dir="$(rospack find sl_bringup)"
  rostest --package=sl_bringup --pkgdir="$pkg_dir" "$pkg_dir/test/bag_${name%_approach}.test" \
    write:="$root/test/expectations/$name.yaml"
  export ROS_MASTER_URI=http://localhost:$port
}

# The wall: from when it is inside the working volume (0.8 m) to the stop; the leg: the whole approach.
record wall_approach "$root/test/scenes/wall_1000.yaml" "s.nearest_distance < 0.78"
record leg_approach "$(rospack find sl_sim)/scenes/table_leg_20mm.yaml" "s.command == ObstacleStatus.COMMAND_DRIVE"
echo "bags in $root/test/bags, expectations in $root/test/expectations"
