#!/usr/bin/env python
"""Login chain 3/3 (rospy): the login service, magic number 42."""

import rospy
from hri_lab.srv import Login, LoginResponse


def handle(req):
    if req.username and req.magic_number == 42:
        return LoginResponse(True, "Welcome, %s!" % req.username)
    return LoginResponse(success=False, message="Login failed: wrong magic number")


if __name__ == "__main__":
    rospy.init_node("login_server")
    rospy.Service("login", Login, handle)
    rospy.loginfo("login server ready")
    rospy.spin()
