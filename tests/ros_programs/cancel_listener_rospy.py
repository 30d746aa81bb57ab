#!/usr/bin/env python
"""A listener of an action's ROS 1 cancel topic, as actionlib's server reads it: each cancel's goal
id and stamp (a ROS 1 client may send the id alone; ROS fills the stamp)."""

import rospy
from actionlib_msgs.msg import GoalID


def callback(cancel):
    print("cancel %s stamp %d.%09d" % (cancel.id, cancel.stamp.secs, cancel.stamp.nsecs), flush=True)


def listener():
    rospy.init_node("cancel_listener")
    rospy.Subscriber("/test_action/cancel", GoalID, callback)
    print("listening", flush=True)
    rospy.spin()


if __name__ == "__main__":
    listener()
