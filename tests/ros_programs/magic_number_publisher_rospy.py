#!/usr/bin/env python
"""Login chain 1/3 (rospy): publishes a random magic number on /magic_number, 5 a second."""

import random

import rospy
from std_msgs.msg import Int64

if __name__ == "__main__":
    rospy.init_node("magic_number_publisher")
    pub = rospy.Publisher("magic_number", Int64, queue_size=10)
    rate = rospy.Rate(5)
    try:
        while not rospy.is_shutdown():
            pub.publish(Int64(random.choice([7, 42, 13])))
            rate.sleep()
    except rospy.ROSInterruptException:
        pass
