#!/usr/bin/env bash
# A real ROS 1 system, recorded: roscore on a free port, Debian's robot_state_publisher with a
# URDF as /robot_description, a rospy publisher of a known joint motion (publish_joint_states.py)
# and `rosbag record /tf /tf_static /joint_states`. Writes OUT_DIR/system.bag (and the logs).
#
#   record_ros1_system.sh URDF OUT_DIR [SECONDS=3] [RATE_HZ=50]
#
# Exit 0 with the bag written; 77 (ctest's skip) when the ROS 1 packages are not installed
# (scripts/setup.sh --ros installs them); 1 on any failure. Every process it starts is in a
# process group of its own and is stopped by that group's id on exit (SIGINT, then SIGKILL after
# a timeout), so no process outlives the script; each step has a timeout.
set -euo pipefail

urdf="${1:?usage: record_ros1_system.sh URDF OUT_DIR [SECONDS] [RATE_HZ]}"
out="${2:?usage: record_ros1_system.sh URDF OUT_DIR [SECONDS] [RATE_HZ]}"
seconds="${3:-3}"
rate="${4:-50}"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
rsp=/usr/lib/robot_state_publisher/robot_state_publisher
py=/usr/bin/python3  # Debian's Python: rospy is packaged for it (not for a pyenv python3)

rm -rf "$out"  # no bag of an earlier run is left for the tests when this one skips or fails
missing=()
for tool in roscore rosparam rosbag; do command -v "$tool" >/dev/null || missing+=("$tool"); done
[ -x "$rsp" ] || missing+=("robot_state_publisher")
"$py" -c 'import rospy, sensor_msgs.msg' 2>/dev/null || missing+=("python3-rospy")
if [ ${#missing[@]} -gt 0 ]; then
  echo "record_ros1_system.sh: SKIP: ROS 1 tools not installed (${missing[*]}); run" \
       "scripts/setup.sh --ros" >&2
  exit 77
fi

mkdir -p "$out/home" "$out/log"
export ROS_HOME="$out/home" ROS_LOG_DIR="$out/log" ROS_HOSTNAME=127.0.0.1
unset ROS_IP ROS_NAMESPACE
port="$("$py" -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
export ROS_MASTER_URI="http://127.0.0.1:$port"

groups=()  # process group ids of what we started, in start order
start() {  # start LOG CMD...: runs CMD in a new process group; sets $started to its pid
  local log="$1"; shift
  setsid "$@" >"$out/$log" 2>&1 &
  started=$!
  groups+=("$started")
}
stop_group() {  # stop_group PGID: SIGINT (ROS nodes close cleanly), SIGKILL after 10 s
  local g="$1" i
  kill -INT -- "-$g" 2>/dev/null || return 0
  for i in $(seq 100); do kill -0 -- "-$g" 2>/dev/null || return 0; sleep 0.1; done
  echo "record_ros1_system.sh: process group $g ignored SIGINT for 10 s; killing it" >&2
  kill -KILL -- "-$g" 2>/dev/null || true
}
cleanup() {
  local i
  for ((i = ${#groups[@]} - 1; i >= 0; i--)); do stop_group "${groups[$i]}"; done
}
trap cleanup EXIT
fail() { echo "record_ros1_system.sh: $*" >&2; for f in "$out"/*.log; do echo "--- $f" >&2; tail -n 20 "$f" >&2; done; exit 1; }

start roscore.log roscore -p "$port"
for i in $(seq 150); do  # the master answers within 15 s
  if timeout 5 rosparam set /semgraph_probe 1 >/dev/null 2>&1; then break; fi
  [ "$i" = 150 ] && fail "roscore did not answer on $ROS_MASTER_URI within 15 s"
  sleep 0.1
done
timeout 10 rosparam set robot_description "$(cat "$urdf")" || fail "rosparam set robot_description"

start robot_state_publisher.log "$rsp"
start record.log rosbag record -O "$out/system.bag" /tf /tf_static /joint_states __name:=semgraph_record
record_group=$started
# The publisher waits for both subscribers, then publishes SECONDS of motion.
timeout $((seconds + 40)) "$py" "$here/publish_joint_states.py" "$rate" "$seconds" \
  >"$out/publisher.log" 2>&1 || fail "the joint state publisher failed"
sleep 0.5  # the last /tf of robot_state_publisher reaches the recorder
# `rosbag record` is a Python wrapper of /usr/lib/rosbag/record: SIGINT the recorder itself
# (it closes the bag: index, connection records), then the wrapper exits on its own.
recorder="$(pgrep -P "$record_group" -x record || true)"
[ -n "$recorder" ] || fail "no recorder process under rosbag record ($record_group)"
kill -INT "$recorder"
for i in $(seq 100); do kill -0 "$record_group" 2>/dev/null || break; sleep 0.1; done
cleanup
groups=()
[ -f "$out/system.bag" ] || fail "rosbag record wrote no $out/system.bag"
echo "record_ros1_system.sh: wrote $out/system.bag ($(stat -c %s "$out/system.bag") bytes)"
