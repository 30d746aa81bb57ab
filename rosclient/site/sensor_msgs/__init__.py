"""sensor_msgs' Python helpers (point_cloud2.py); its messages, `sensor_msgs.msg`, are made from their
definitions (interfaces/share/sensor_msgs)."""
