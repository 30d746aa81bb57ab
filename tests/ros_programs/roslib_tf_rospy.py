#!/usr/bin/env python
"""ROS 1's remaining basics as public rospy scripts use them: roslib.load_manifest (a no-op under
catkin), roslib.message.get_message_class, tf/tfMessage, and get_num_connections counting the lab's
own subscriber to the command topic (a teleop node waits for it)."""

import roslib

roslib.load_manifest("beginner_tutorials")
import rospy  # noqa: E402 - after load_manifest, as those scripts are written
from roslib.message import get_message_class  # noqa: E402 - after load_manifest, as those scripts are written
from tf.msg import tfMessage  # noqa: E402 - after load_manifest, as those scripts are written

print("class", get_message_class("std_msgs/String")._type, get_message_class("nope/Nope"))
print("tf", tfMessage._type, tfMessage().transforms)
rospy.init_node("teleop")
pub = rospy.Publisher("/cartesian_velocity_controller/command", get_message_class("geometry_msgs/Twist"), queue_size=1)
print("connections", pub.get_num_connections(), flush=True)
