#!/usr/bin/env python
"""A listener that reads ROS 1's header.seq of each message it hears."""

import rospy
from beginner_tutorials.msg import HeaderString


def callback(data):
    print("I heard seq %d: %s" % (data.header.seq, data.data), flush=True)


def listener():
    rospy.init_node("header_listener", anonymous=True)
    rospy.Subscriber("chatter_header", HeaderString, callback)
    print("listening", flush=True)
    rospy.spin()


if __name__ == "__main__":
    listener()
