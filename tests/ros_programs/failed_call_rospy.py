#!/usr/bin/env python
"""Calls a service no program provides yet (in `serve --exercises`): a failed call."""

import rospy
from hri_lab.srv import DivideInts

rospy.init_node("divider")
try:
    print(rospy.ServiceProxy("/divide_ints", DivideInts)(7, 2))
except rospy.ServiceException as e:
    print("Service call failed: %s" % e, flush=True)
