"""The ROS side: the C API over roscpp (wrapper), the layout check, the build of a node, a private rosmaster, the demo."""
