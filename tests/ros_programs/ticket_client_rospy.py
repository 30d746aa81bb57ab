#!/usr/bin/env python
"""A client that shows a ticket in its connection header (rospy's ServiceProxy(headers=...)) and
prints the server's header from the response."""

import rospy
from example_interfaces.srv import AddTwoInts

if __name__ == "__main__":
    rospy.init_node("ticket_client")
    rospy.wait_for_service("ticketed_add")
    add = rospy.ServiceProxy("ticketed_add", AddTwoInts, headers={"ticket": "A-113"})
    resp = add(40, 2)
    header = resp._connection_header
    print("sum %s" % resp.sum, flush=True)
    print(
        "answered by %s for %s (%s, md5 %s)"
        % (header["callerid"], header["service"], header["type"], header["md5sum"]),
        flush=True,
    )
