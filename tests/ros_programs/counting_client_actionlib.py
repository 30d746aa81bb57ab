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
printing = threading.Lock()  # feedback comes on rospy's thread: one line at a time on stdout


def say(line):
    with printing:
        print(line, flush=True)


def feedback(fb):
    say("at %d" % fb.current)
    if fb.current >= 2:
        two.set()


client.send_goal(CountingGoal(count=10), feedback_cb=feedback)
two.wait(60)
client.cancel_goal()
client.wait_for_result(rospy.Duration(30))
say("state %d reached %d" % (client.get_state(), client.get_result().reached))
