#!/usr/bin/env python
"""ROS 1's tf tutorial listener (rospy, tf): waits for `carrot`, then prints its distance from
`plate_marker` and where `plate_marker` is in `panda_link0`, with tf.TransformListener."""

import math

import rospy
import tf

if __name__ == "__main__":
    rospy.init_node("tf_listener")
    listener = tf.TransformListener()
    # the program's frames and the lab's robot arrive on /tf separately: wait for both
    listener.waitForTransform("/plate_marker", "/carrot", rospy.Time(0), rospy.Duration(30.0))
    listener.waitForTransform("/panda_link0", "/plate_marker", rospy.Time(0), rospy.Duration(30.0))
    rate = rospy.Rate(2.0)
    for _ in range(3):
        try:
            (trans, rot) = listener.lookupTransform("/plate_marker", "/carrot", rospy.Time(0))
            (marker, _) = listener.lookupTransform("/panda_link0", "/plate_marker", rospy.Time(0))
        except (tf.LookupException, tf.ConnectivityException, tf.ExtrapolationException):
            rate.sleep()  # a retry a period later, not three at once
            continue
        print("carrot radius: %.4f" % math.sqrt(trans[0] ** 2 + trans[1] ** 2), flush=True)
        print("plate_marker in panda_link0: %.4f %.4f %.4f" % tuple(marker), flush=True)
        rate.sleep()
