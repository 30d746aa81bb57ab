"""Recordings in the formats of ROS: rosbag1 and rosbag2 read and written (`hri-lab bag`)."""
