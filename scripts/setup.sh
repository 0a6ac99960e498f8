#!/usr/bin/env bash
# Installs the Debian 12 packages semgraph needs, skipping those already installed.
#
#   scripts/setup.sh [--clang] [--bench] [--dot] [--dds] [--ros]
#
#   (always)  cmake g++ make pkgconf libeigen3-dev libgtest-dev libbenchmark-dev libyaml-cpp-dev
#             pybind11-dev python3-dev python3-numpy python3-pytest python3-scipy (Python module)
#             liburdfdom-dev (semgraph::models, URDF) liborocos-kdl-dev (the kinematics and wrench
#             cross-check tests) libmrpt-poses-dev (the uncertainty cross-check tests: MRPT's
#             pose PDFs)
#   --clang   clang libclang-rt-14-dev clang-format (clang++ builds, sanitizers, libFuzzer; formatting)
#   --bench   libtf2-dev valgrind libdart-dev (the tf2 comparison benchmarks, callgrind counts; DART:
#             the acceleration cross-check tests, skipped without it)
#   --dot     graphviz                   (rendering scene graphs exported as DOT)
#   --dds     cyclonedds-dev cyclonedds-tools (semgraph::dds, distributed scenes; idlc, ddsperf)
#   --ros     libzstd-dev liblz4-dev libsqlite3-dev libbz2-dev (semgraph::ros: bag chunks, rosbag2
#             sqlite3) zlib1g-dev (its tests' CRC32); python3-rosbag python3-roslz4
#             python3-tf2-msgs python3-sensor-msgs python3-geometry-msgs python3-std-msgs
#             python3-nav-msgs (the ROS 1 bag and message fixtures); ros-core
#             ros-robot-state-publisher (roscore, rospy, rostopic, rosbag record,
#             robot_state_publisher: the recorded ROS 1 system of tests/ros/ros1_system);
#             nodejs npm only when `node` is not on PATH (the tests' fixtures are written with
#             Foxglove's npm packages; Debian's npm conflicts with another node)
#
# Idempotent: when everything is installed it only says so. Installing needs root; as
# another user it fails, printing the command to run.
set -euo pipefail

usage() { sed -n '2,26p' "$0" | sed 's/^# \{0,1\}//'; }

packages=(cmake g++ make pkgconf libeigen3-dev libgtest-dev libbenchmark-dev libyaml-cpp-dev pybind11-dev python3-dev python3-numpy python3-pytest python3-scipy liburdfdom-dev liborocos-kdl-dev libmrpt-poses-dev)
for arg in "$@"; do
  case "$arg" in
    --clang) packages+=(clang libclang-rt-14-dev clang-format) ;;
    --bench) packages+=(libtf2-dev valgrind libdart-dev) ;;
    --dot) packages+=(graphviz) ;;
    --dds) packages+=(cyclonedds-dev cyclonedds-tools) ;;
    --ros)
      packages+=(libzstd-dev liblz4-dev libsqlite3-dev libbz2-dev zlib1g-dev python3-rosbag
                 python3-roslz4 python3-tf2-msgs python3-sensor-msgs python3-geometry-msgs
                 python3-std-msgs python3-nav-msgs ros-core ros-robot-state-publisher)
      if ! command -v node >/dev/null 2>&1; then packages+=(nodejs npm); fi
      ;;
    -h | --help) usage; exit 0 ;;
    *) echo "setup.sh: unknown option '$arg'" >&2; usage >&2; exit 2 ;;
  esac
done

is_installed() {
  dpkg -s "$1" 2>/dev/null | grep -q '^Status: install ok installed$'
}

missing=()
for pkg in "${packages[@]}"; do
  if ! is_installed "$pkg"; then missing+=("$pkg"); fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed: ${packages[*]}"
  exit 0
fi

echo "setup: missing packages: ${missing[*]}"
install_cmd="apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
  echo "setup: installing packages needs root. Run:" >&2
  echo "  sudo sh -c '$install_cmd'" >&2
  exit 1
fi

echo "setup: + apt-get update"
apt-get update
echo "setup: + apt-get install -y --no-install-recommends ${missing[*]}"
DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"

for pkg in "${missing[@]}"; do
  if ! is_installed "$pkg"; then
    echo "setup: package $pkg is still not installed" >&2
    exit 1
  fi
done
echo "setup: installed ${missing[*]}"
