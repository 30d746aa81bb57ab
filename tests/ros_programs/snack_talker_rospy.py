#!/usr/bin/env python
"""A talker that tells its listeners more than its messages: extra fields in its connection header
(rospy's Publisher(headers=...)), latched; a second publisher of the topic adds its own."""

import rospy
from std_msgs.msg import String


def talker():
    pub = rospy.Publisher("snacks", String, headers={"snack": "pretzels", "shelf": "3"}, latch=True, queue_size=10)
    # a second publisher of the topic: rospy's publishers of one topic share one connection header
    rospy.Publisher("snacks", String, headers={"drink": "tea"}, queue_size=10)
    rospy.init_node("snack_talker")
    r = rospy.Rate(5)
    while not rospy.is_shutdown():
        pub.publish("snack time %s" % rospy.get_time())
        r.sleep()


if __name__ == "__main__":
    try:
        talker()
    except rospy.ROSInterruptException:
        pass
