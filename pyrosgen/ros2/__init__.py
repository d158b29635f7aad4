"""The ROS 2 target (issue 31): ROS 2 message definitions, the rcl wrapper, the build."""
