"""Fixtures for the real-ROS tests: a private rosmaster per test on
127.0.0.1 at a free port, stopped (with every process the test spawned
through it) even when the test fails."""

import pytest

from pyrosgen.rosmaster import ros_master


@pytest.fixture
def ros(tmp_path):
    with ros_master(tmp_path / "ros") as env:
        yield env
