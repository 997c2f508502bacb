"""ROS 2 integration (the ``ros2`` extra): message conversions and nodes.

Nothing in navlab's core imports this package or rclpy.
"""
