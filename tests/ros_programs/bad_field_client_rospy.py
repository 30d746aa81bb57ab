#!/usr/bin/env python
"""A client with a mistake: the request field 'c' does not exist in AddTwoInts."""

import rospy
from example_interfaces.srv import AddTwoInts, AddTwoIntsRequest

rospy.init_node("bad_client")
rospy.wait_for_service("add_two_ints", timeout=30)
print(rospy.ServiceProxy("add_two_ints", AddTwoInts)(AddTwoIntsRequest(a=1, c=2)))
