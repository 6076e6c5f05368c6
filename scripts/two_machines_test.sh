#!/usr/bin/env bash
# Two machines on one host: the robot and the workstation in two network namespaces joined by a
# veth pair (10.200.0.1 robot, 10.200.0.2 workstation; nothing else is reachable from either).
# The robot side runs roscore and launch/sim.launch command_mode:=filter headless, the master with
# it; the workstation side runs scripts/two_machines_client.py, which subscribes to what
# launch/view.launch's rviz shows, checks that the map, cloud and status arrive, prints the bytes per
# second they carry (and what the link carried), and turns the robot through cmd_vel_in.
#
#   scripts/two_machines_test.sh [--junit FILE] [--rviz SECONDS] [WORKSPACE]
#
#   --junit FILE     also write the verdict as a JUnit XML file (make test: sl_bringup/two_machines.xml)
#   --rviz SECONDS   instead of the client: rviz of view.launch under Xvfb on the workstation side,
#                    and the bytes the link carried to it over SECONDS (the figure in doc/results.md)
#   --shot FILE.png  with --rviz: a screenshot of that rviz (xwd, ImageMagick)
#
# Exit status: 0 passed, 1 failed, 77 skipped (no network namespaces here: not root, no `ip`, or the
# kernel refused; the line "SKIPPED: <reason>" says which). Names carry this script's PID, so parallel
# runs do not collide; the namespaces, their processes and the veth pair go on exit.
set -uo pipefail
root="$(cd -P "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
junit=""
rviz_seconds=""
shot=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --junit) junit="$2"; shift 2 ;;
    --rviz) rviz_seconds="$2"; shift 2 ;;
    --shot) shot="$2"; shift 2 ;;
    -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
    *) break ;;
  esac
done
ws="${1:-$root/catkin_ws}"
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH PYTHONNOUSERSITE=1
unset PYTHONPATH PYTHONHOME
set +u
# shellcheck disable=SC1091
source "$ws/devel/setup.bash"
set -u

SKIP=77
robot_ns="sl_robot_$$"
ws_ns="sl_ws_$$"
robot_if="slr$$"
ws_if="slw$$"
robot_ip=10.200.0.1
ws_ip=10.200.0.2
master="http://$robot_ip:11311"
work="$(mktemp -d /tmp/sl_two_machines_XXXXXX)"
log="$work/output.txt"
started=$(date +%s)

# verdict STATUS MESSAGE: prints it, writes the JUnit file when asked, exits.
verdict() {
  local status="$1" message="$2"
  echo "$message" | tee -a "$log"
  if [[ -n "$junit" ]]; then
    mkdir -p "$(dirname "$junit")"
    /usr/bin/python3 - "$junit" "$status" "$message" "$log" "$(( $(date +%s) - started ))" <<'EOF'
import re
import sys
import xml.etree.ElementTree as ET
path, status, message, log, seconds = sys.argv[1:]
# XML 1.0 has no place for control characters (the logs' colour codes)
clean = lambda text: re.sub(r"[\x00-\x08\x0b\x0c\x0e-\x1f]", "", re.sub(r"\x1b\[[0-9;]*m", "", text))
suite = ET.Element("testsuite", name="sl_bringup.two_machines", tests="1", errors="0",
                   failures="1" if status == "1" else "0", skipped="1" if status == "77" else "0")
case = ET.SubElement(suite, "testcase", classname="sl_bringup.TwoMachines", name="robot_and_workstation",
                     time=seconds)
if status == "1":
    ET.SubElement(case, "failure", message=clean(message)).text = clean(message)
elif status == "77":
    ET.SubElement(case, "skipped", message=clean(message))
with open(log, errors="replace") as f:
    ET.SubElement(case, "system-out").text = clean(f.read())
ET.ElementTree(suite).write(path, encoding="utf-8", xml_declaration=True)
EOF
  fi
  exit "$status"
}

# Ends every process in our namespaces (only ours are there), then the namespaces and the veth pair.
# shellcheck disable=SC2317  # called by cleanup
in_namespaces() {
  local ns
  for ns in "$ws_ns" "$robot_ns"; do ip netns pids "$ns" 2>/dev/null; done
}
# shellcheck disable=SC2317  # called by the EXIT trap
cleanup() {
  local ns sig pids
  for sig in INT TERM KILL; do
    pids=$(in_namespaces)
    [[ -z "$pids" ]] && break
    # shellcheck disable=SC2086
    kill -"$sig" $pids 2>/dev/null
    for _ in $(seq 10); do
      [[ -z "$(in_namespaces)" ]] && break
      sleep 0.5
    done
  done
  for ns in "$ws_ns" "$robot_ns"; do
    ip netns del "$ns" 2>/dev/null
  done
  rm -rf "$work"
}
trap cleanup EXIT
trap 'verdict 1 "FAILED: interrupted"' INT TERM

# Namespaces left by runs of this script that were killed (their PID is gone), with what still runs there.
for ns in $(ip netns list 2>/dev/null | grep -oE '^sl_(robot|ws)_[0-9]+'); do
  if ! kill -0 "${ns##*_}" 2>/dev/null; then
    # shellcheck disable=SC2046
    kill -KILL $(ip netns pids "$ns" 2>/dev/null) 2>/dev/null
    ip netns del "$ns" 2>/dev/null
  fi
done

command -v ip > /dev/null || verdict $SKIP "SKIPPED: no 'ip' command (iproute2) to create network namespaces"
[[ $(id -u) -eq 0 ]] || verdict $SKIP "SKIPPED: creating network namespaces needs root (running as uid $(id -u))"
if ! err=$(ip netns add "$robot_ns" 2>&1 && ip netns add "$ws_ns" 2>&1); then
  verdict $SKIP "SKIPPED: cannot create network namespaces: $err"
fi
if ! err=$(ip netns exec "$robot_ns" true 2>&1); then
  verdict $SKIP "SKIPPED: cannot run a process in a network namespace: $err"
fi
if ! err=$(ip link add "$robot_if" netns "$robot_ns" type veth peer name "$ws_if" netns "$ws_ns" 2>&1); then
  verdict $SKIP "SKIPPED: cannot create a veth pair between the namespaces: $err"
fi
if ! { ip -n "$robot_ns" link set lo up && ip -n "$ws_ns" link set lo up &&
  ip -n "$robot_ns" addr add "$robot_ip/24" dev "$robot_if" && ip -n "$ws_ns" addr add "$ws_ip/24" dev "$ws_if" &&
  ip -n "$robot_ns" link set "$robot_if" up && ip -n "$ws_ns" link set "$ws_if" up; }; then
  verdict 1 "FAILED: cannot set up the addresses of the veth pair"
fi
echo "robot: namespace $robot_ns, $robot_ip, master $master; workstation: namespace $ws_ns, $ws_ip" | tee -a "$log"

# robot_run / ws_run CMD...: a command on that side, with ROS_IP and ROS_MASTER_URI as on a machine.
robot_run() {
  ip netns exec "$robot_ns" env ROS_IP="$robot_ip" ROS_MASTER_URI="$master" ROS_HOME="$work/robot" "$@"
}
ws_run() {
  ip netns exec "$ws_ns" env ROS_IP="$ws_ip" ROS_MASTER_URI="$master" ROS_HOME="$work/workstation" "$@"
}

robot_run roscore -p 11311 > "$work/roscore.log" 2>&1 &
robot_run roslaunch --wait "$root/launch/sim.launch" command_mode:=filter > "$work/robot.log" 2>&1 &
robot_pid=$!
for _ in $(seq 40); do
  ws_run /usr/bin/python3 -c "import rosgraph, sys; sys.exit(not rosgraph.is_master_online())" && break
  sleep 0.5
done

if [[ -n "$rviz_seconds" ]]; then
  # Xvfb inside the workstation's namespace (its X socket is the namespace's own).
  display=":$(( 200 + $$ % 500 ))"
  ws_run Xvfb "$display" -screen 0 1400x900x24 -nolisten tcp > "$work/xvfb.log" 2>&1 &
  sleep 2
  ws_run env DISPLAY="$display" roslaunch "$root/launch/view.launch" > "$work/rviz.log" 2>&1 &
  sleep 25  # the simulated system and rviz up, every display subscribed
  rx() { ip netns exec "$ws_ns" cat "/sys/class/net/$ws_if/statistics/rx_bytes"; }
  b0=$(rx); t0=$(date +%s.%N)
  sleep "$rviz_seconds"
  b1=$(rx); t1=$(date +%s.%N)
  ws_run rosnode info -q /rviz 2>&1 | sed -n '/^Subscriptions/,/^$/p' | tee -a "$log"
  if [[ -n "$shot" ]]; then
    ws_run env DISPLAY="$display" xwd -root -silent > "$work/screen.xwd" &&
      /usr/bin/convert "xwd:$work/screen.xwd" -strip "png:$shot" && echo "screenshot: $shot"
  fi
  kill -0 $robot_pid 2>/dev/null || { tail -n 20 "$work/robot.log"; verdict 1 "FAILED: sim.launch ended"; }
  grep -q "process has died" "$work/rviz.log" && { tail -n 20 "$work/rviz.log"; verdict 1 "FAILED: rviz died"; }
  rate=$(/usr/bin/python3 -c "print('%.3f' % (($b1 - $b0) / ($t1 - $t0) / 1e6))")
  verdict 0 "rviz (view.launch) on the workstation received $rate MB/s over the link in $rviz_seconds s"
fi

ws_run /usr/bin/python3 "$root/scripts/two_machines_client.py" --link "$ws_if" 2>&1 | tee -a "$log"
status=${PIPESTATUS[0]}
if [[ $status -ne 0 ]]; then
  if ! kill -0 $robot_pid 2>/dev/null; then
    echo "sim.launch on the robot side ended; its last lines:" | tee -a "$log"
  fi
  tail -n 25 "$work/robot.log" | tee -a "$log"
  verdict 1 "$(grep -m1 '^FAILED' "$log" || echo "FAILED: the workstation's client exited with $status")"
fi
verdict 0 "PASSED in $(( $(date +%s) - started )) s"
