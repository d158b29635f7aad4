#!/usr/bin/env bash
# Install, only when missing, the Debian packages pyrosgen needs.
# Idempotent: when everything is present it prints one line and installs nothing.
set -euo pipefail

PKGS=(
  # proofs
  coq libcoq-flocq ocaml-nox
  # C toolchain
  g++ gcc make pkg-config cmake
  # ROS 1 runtime, master and message packages
  libroscpp-dev python3-rosmaster python3-rospy python3-roslib python3-rosgraph catkin
  # the tools a user watches a node with: rostopic, rosnode, roslaunch, rosrun
  python3-rostopic python3-rosnode python3-roslaunch rosbash
  # the C++ headers of every standard message package the front end knows
  # (pyrosgen/frontend/msgdeb.py: DEBIAN_DEV, one for each)
  libstd-msgs-dev libgeometry-msgs-dev libnav-msgs-dev libsensor-msgs-dev
  libactionlib-msgs-dev libdiagnostic-msgs-dev libshape-msgs-dev libstereo-msgs-dev
  libtrajectory-msgs-dev libvisualization-msgs-dev libros-rosgraph-msgs-dev
  libactionlib-dev libdynamic-reconfigure-config-init-mutex-dev libbond-dev libroscpp-msg-dev
  # their Python modules, for rostopic and rospy
  python3-std-msgs python3-geometry-msgs python3-nav-msgs python3-sensor-msgs
  # C++ classes for custom .msg types (msg_paths)
  python3-gencpp python3-genmsg ros-std-msgs ros-geometry-msgs ros-nav-msgs ros-sensor-msgs
  # the .msg definitions of every standard message package the front end knows, read
  # by the second, independent reading of a model (pyrosgen/nversion, DESIGN.md section 7)
  ros-actionlib-msgs ros-diagnostic-msgs ros-shape-msgs ros-stereo-msgs ros-trajectory-msgs
  ros-visualization-msgs ros-rosgraph-msgs ros-roscpp-msg
  # message packages of custom messages in the catkin workspace (message_generation)
  ros-message-generation ros-message-runtime python3-genpy
  # second verifier of the printed C
  frama-c-base why3 z3
  # pictures, python venv
  graphviz python3-venv
)
# Optional, `make deps VIEWERS=1`: rviz, to look at a running node's messages
# (a large Qt/OGRE tree, so not by default). rqt_graph is not packaged by
# Debian (its ROS 1 has no rqt): `rosnode info`, `rostopic list -v` and
# `pyrosgen diagram` show a node's graph instead (README, section 5).
if [ "${VIEWERS:-0}" = 1 ]; then
  PKGS+=(rviz)
fi

missing=()
for p in "${PKGS[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "deps: all ${#PKGS[@]} Debian packages present"
  exit 0
fi

echo "deps: installing missing Debian packages: ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null; then SUDO="sudo -n"; else
    echo "deps: error: not root and no sudo; install these packages: ${missing[*]}" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
# The package lists may be empty on a fresh machine; update once.
$SUDO apt-get update -qq >/dev/null
# -qq: apt's errors only (dpkg's unpacking lines are not the user's business)
$SUDO apt-get install -y -qq -o Dpkg::Use-Pty=0 --no-install-recommends "${missing[@]}" >/dev/null
echo "deps: installed ${#missing[@]} Debian package(s)"
