#!/usr/bin/env python
"""A client of the counting action that preempts it at 2."""

import threading

import actionlib
import rospy
from cpp_package.msg import CountingAction, CountingGoal

rospy.init_node("counting_client")
client = actionlib.SimpleActionClient("counting", CountingAction)
client.wait_for_server(rospy.Duration(30))
two = threading.Event()
client.send_goal(
    CountingGoal(count=10),
    feedback_cb=lambda fb: (print("at %d" % fb.current, flush=True), fb.current >= 2 and two.set()),
)
two.wait(60)
client.cancel_goal()
client.wait_for_result(rospy.Duration(30))
print("state %d reached %d" % (client.get_state(), client.get_result().reached), flush=True)
