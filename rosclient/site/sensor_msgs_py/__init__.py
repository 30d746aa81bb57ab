"""sensor_msgs_py (ROS 2): point_cloud2's helpers for sensor_msgs/PointCloud2 (sensor_msgs_py/point_cloud2.py)."""
