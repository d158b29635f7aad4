#!/usr/bin/env bash
# Install, only when missing, the pinned ROS 2 Kilted wheels of
# requirements-ros2.txt into .venv-ros2 (a virtual environment of their own,
# see that file).  Idempotent: a stamp records the requirements installed.
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${PYROSGEN_ROS2_PREFIX:-.venv-ros2}
STAMP="$VENV/.pyrosgen-ros2-installed"
if [[ -f "$STAMP" ]] && cmp -s "$STAMP" requirements-ros2.txt; then
  echo "ros2-deps: the ROS 2 wheels of requirements-ros2.txt are installed in $VENV"
  exit 0
fi
test -x "$VENV/bin/python" || /usr/bin/python3 -m venv "$VENV"
echo "ros2-deps: installing the ROS 2 Kilted wheels of requirements-ros2.txt into $VENV"
"$VENV/bin/python" -m pip install -q --disable-pip-version-check -r requirements-ros2.txt
cp requirements-ros2.txt "$STAMP"
