"""The ROS client libraries for students' programs (rospy, rclpy, actionlib, the message packages)
over the lab's rosbridge endpoint; `hri-lab run` and `hri-lab launch` start programs with them.

- interfaces.py: the import finder for `<pkg>.msg|srv|action` (the classes: interfaces)
- connection.py: the rosbridge v2 WebSocket client
- process.py: what rospy and rclpy share in one program
- site/: the importable top-level packages (rospy, rclpy, actionlib, cv_bridge), on sys.path only in
  a program that boot.py starts
- boot.py: a program's start (finder, sys.path, argv); run.py and launch.py: the commands
"""
