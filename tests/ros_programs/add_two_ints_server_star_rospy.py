#!/usr/bin/env python
"""The rospy tutorial's service, as it is written: a star import of the package's srv module
(genpy's AddTwoInts, AddTwoIntsRequest, AddTwoIntsResponse)."""

import rospy
from beginner_tutorials.srv import *


def handle_add_two_ints(req):
    print("Returning [%s + %s = %s]" % (req.a, req.b, (req.a + req.b)), flush=True)
    return AddTwoIntsResponse(req.a + req.b)


def add_two_ints_server():
    rospy.init_node("add_two_ints_server")
    rospy.Service("add_two_ints", AddTwoInts, handle_add_two_ints)
    try:
        rospy.Service("add_two_ints", AddTwoInts, handle_add_two_ints)
    except rospy.ServiceException as e:
        print("Second service refused: %s" % e, flush=True)
    print("Ready to add two ints.", flush=True)
    rospy.spin()


if __name__ == "__main__":
    add_two_ints_server()
