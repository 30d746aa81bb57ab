"""Recordings: the services every world serves alike to record it live, and ROS's formats: rosbag1
and rosbag2 read and written (`hri-lab bag`)."""
