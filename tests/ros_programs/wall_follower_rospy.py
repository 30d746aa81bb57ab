#!/usr/bin/env python
"""A wall follower (rospy), as the EE-381 handout writes it for ROS 1: subscribe /scan, publish
/cmd_vel; the obstacle kept on the right, DISTANCE m away (the rclpy reference's rule,
wall_follower_rclpy.py, in a rospy node)."""

import math

import rospy
from geometry_msgs.msg import Twist
from sensor_msgs.msg import LaserScan

DISTANCE = 0.40  # m from the wall on the right
SPEED = 0.15  # m/s


def nearest(ranges, first, last):
    best = (math.inf, (first + last) // 2)
    for i in range(first, last + 1):
        r = ranges[i % len(ranges)]
        if math.isfinite(r) and r < best[0]:
            best = (r, i)
    return best


def on_scan(scan):
    front, _ = nearest(scan.ranges, -30, 30)
    right, index = nearest(scan.ranges, 200, 340)
    msg = Twist()
    if front < DISTANCE + 0.2:
        msg.linear.x, msg.angular.z = 0.02, 1.2
    elif not math.isfinite(right) or right > 1.2:
        msg.linear.x, msg.angular.z = SPEED, -0.6
    else:
        turn = -2.5 * (right - DISTANCE) + 1.5 * math.radians(index - 270)
        msg.linear.x, msg.angular.z = SPEED, max(-1.5, min(1.5, turn))
    publisher.publish(msg)


if __name__ == "__main__":
    rospy.init_node("wall_follower")
    publisher = rospy.Publisher("cmd_vel", Twist, queue_size=10)
    rospy.Subscriber("scan", LaserScan, on_scan)
    rospy.loginfo("wall follower ready")
    rospy.spin()
