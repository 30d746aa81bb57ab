#!/usr/bin/env python
"""A wrong wall follower (rospy): it turns on the spot forever. Graded, it fails as a stall
(tests/e2e/test_grade_wall.py)."""

import rospy
from geometry_msgs.msg import Twist

if __name__ == "__main__":
    rospy.init_node("spinner")
    publisher = rospy.Publisher("cmd_vel", Twist, queue_size=10)
    rate = rospy.Rate(10)
    msg = Twist()
    msg.angular.z = 1.0
    while not rospy.is_shutdown():
        publisher.publish(msg)
        rate.sleep()
