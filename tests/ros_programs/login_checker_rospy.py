#!/usr/bin/env python
"""Login chain 2/3 (rospy): logs in with every magic number it hears."""

import rospy
from hri_lab.srv import Login
from std_msgs.msg import Int64


def main():
    rospy.init_node("login_checker")
    user = rospy.get_param("~user", "ada")
    rospy.wait_for_service("/login", timeout=60)
    login = rospy.ServiceProxy("/login", Login)

    def heard(msg):
        answer = login(user, msg.data)
        rospy.loginfo("magic %d: success=%s %s", msg.data, answer.success, answer.message)

    rospy.Subscriber("magic_number", Int64, heard, queue_size=1)
    rospy.spin()


if __name__ == "__main__":
    main()
