#!/usr/bin/env python
"""A listener that reads who sent each message, and what else it said, from msg._connection_header."""

import rospy
from std_msgs.msg import String


def callback(msg):
    header = msg._connection_header
    print(
        "%s on %s (%s, md5 %s, latching %s) offers %s from shelf %s with %s"
        % (
            header["callerid"],
            header["topic"],
            header["type"],
            header["md5sum"],
            header["latching"],
            header.get("snack", "nothing"),
            header.get("shelf", "?"),
            header.get("drink", "nothing to drink"),
        ),
        flush=True,
    )


def listener():
    rospy.init_node("snack_listener", anonymous=True)
    mine = String("built here")  # told before subscribing: a latched message's callback may come at once
    print("a message built here has a connection header: %s" % hasattr(mine, "_connection_header"), flush=True)
    rospy.Subscriber("snacks", String, callback)
    rospy.spin()


if __name__ == "__main__":
    listener()
