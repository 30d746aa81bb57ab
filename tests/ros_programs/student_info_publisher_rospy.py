#!/usr/bin/env python
"""Publishes the handout's custom message, StudentInfo, on /student_info at 20 Hz: age counts up."""

import rospy
from student_pkg.msg import StudentInfo

if __name__ == "__main__":
    rospy.init_node("student_info_publisher")
    pub = rospy.Publisher("student_info", StudentInfo, queue_size=10)
    rate = rospy.Rate(20)
    age = 0
    print("publisher ready", flush=True)
    while not rospy.is_shutdown():
        pub.publish(StudentInfo(name="ada", age=age, marks=[1.5, age / 2.0]))
        age += 1
        rate.sleep()
