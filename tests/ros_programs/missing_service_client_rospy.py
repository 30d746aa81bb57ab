#!/usr/bin/env python
"""A client with a mistake: it waits for a service nobody provides (/add_three_ints)."""

import rospy
from example_interfaces.srv import AddTwoInts

rospy.init_node("lost_client")
rospy.wait_for_service("add_three_ints", timeout=0.5)
print(rospy.ServiceProxy("add_three_ints", AddTwoInts)(1, 2))
