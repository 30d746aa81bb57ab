#!/usr/bin/env python
"""A server that reads who calls it, and the ticket they show, from req._connection_header."""

import rospy
from example_interfaces.srv import AddTwoInts, AddTwoIntsResponse


def handle(req):
    header = req._connection_header
    print("call from %s with ticket %s" % (header["callerid"], header.get("ticket", "none")), flush=True)
    return AddTwoIntsResponse(req.a + req.b)


if __name__ == "__main__":
    rospy.init_node("ticket_server")
    rospy.Service("ticketed_add", AddTwoInts, handle)
    print("Ready to add with tickets.", flush=True)
    rospy.spin()
