#!/usr/bin/env python
"""AddTwoInts server (rospy): answers /add_two_ints with a + b."""

import rospy
from example_interfaces.srv import AddTwoInts, AddTwoIntsResponse


def handle_add(req):
    rospy.loginfo("Returning [%s + %s = %s]", req.a, req.b, req.a + req.b)
    return AddTwoIntsResponse(req.a + req.b)


def add_two_ints_server():
    rospy.init_node("add_two_ints_server")
    rospy.Service("add_two_ints", AddTwoInts, handle_add)
    print("Ready to add two ints.", flush=True)
    rospy.spin()


if __name__ == "__main__":
    add_two_ints_server()
