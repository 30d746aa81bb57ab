#!/usr/bin/env python
"""tf's `static_transform_publisher x y z yaw pitch roll frame_id child_frame_id period_in_ms` as a
rospy program (roslibjs's test setup, test/examples/setup_examples.launch, starts
`static_transform_publisher 0 0 0 0 0 0 /world /turtle1 100`): the transform sent on /tf every
period, stamped now, as ROS 1's tf tool sends it."""

import math
import sys

import rospy
import tf2_ros
from geometry_msgs.msg import TransformStamped


def quaternion_from_ypr(yaw: float, pitch: float, roll: float) -> tuple[float, float, float, float]:
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    return (
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
        cr * cp * cy + sr * sp * sy,
    )


if __name__ == "__main__":
    argv = rospy.myargv(sys.argv)
    if len(argv) != 10:
        sys.exit("usage: static_transform_publisher x y z yaw pitch roll frame_id child_frame_id period_in_ms")
    x, y, z, yaw, pitch, roll = (float(v) for v in argv[1:7])
    frame_id, child, period_ms = argv[7].lstrip("/"), argv[8].lstrip("/"), float(argv[9])
    rospy.init_node("static_transform_publisher", anonymous=True)
    broadcaster = tf2_ros.TransformBroadcaster()
    t = TransformStamped()
    t.header.frame_id, t.child_frame_id = frame_id, child
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = x, y, z
    q = quaternion_from_ypr(yaw, pitch, roll)
    t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z, t.transform.rotation.w = q
    rate = rospy.Rate(1000.0 / period_ms)
    while not rospy.is_shutdown():
        t.header.stamp = rospy.Time.now()
        broadcaster.sendTransform(t)
        rate.sleep()
