#!/usr/bin/env python
"""A talker of a message with a Header, built as rospy's test nodes build it: HeaderString(None, text)
(genpy takes None as the field's default; rospy fills the header's seq on publish)."""

import rospy
from beginner_tutorials.msg import HeaderString


def talker():
    pub = rospy.Publisher("chatter_header", HeaderString, queue_size=10)  # before init_node, as rospy allows
    rospy.init_node("header_talker", anonymous=True)
    r = rospy.Rate(10)
    while not rospy.is_shutdown():
        str = "hello world %s" % rospy.get_time()
        pub.publish(HeaderString(None, str))
        r.sleep()


if __name__ == "__main__":
    try:
        talker()
    except rospy.ROSInterruptException:
        pass
