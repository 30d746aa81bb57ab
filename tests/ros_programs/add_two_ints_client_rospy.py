#!/usr/bin/env python
"""AddTwoInts client (rospy): adds the two numbers of its command line with the service."""

import sys

import rospy
from example_interfaces.srv import AddTwoInts


def add_two_ints_client(x, y):
    rospy.wait_for_service("add_two_ints", timeout=float(sys.argv[3]) if len(sys.argv) > 3 else None)
    try:
        add_two_ints = rospy.ServiceProxy("add_two_ints", AddTwoInts)
        resp = add_two_ints(x, y)
        return resp.sum
    except rospy.ServiceException as e:
        print("Service call failed: %s" % e)
        sys.exit(1)


if __name__ == "__main__":
    if len(sys.argv) < 3:
        print("usage: add_two_ints_client_rospy.py X Y [TIMEOUT]")
        sys.exit(1)
    rospy.init_node("add_two_ints_client", anonymous=True)
    x, y = int(sys.argv[1]), int(sys.argv[2])
    print("Requesting %s+%s" % (x, y))
    print("%s + %s = %s" % (x, y, add_two_ints_client(x, y)), flush=True)
