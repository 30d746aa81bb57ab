#!/usr/bin/env python
"""An actionlib client of a counting action (default: the lab's /count): preempts the goal once the
feedback reaches 2, then prints the final state and result."""

import sys
import threading

import actionlib
import rospy
from hri_lab.action import CountAction, CountGoal

rospy.init_node("count_client")
client = actionlib.SimpleActionClient(sys.argv[1] if len(sys.argv) > 1 else "count", CountAction)
if not client.wait_for_server(rospy.Duration(10)):
    rospy.logerr("no action server")
    sys.exit(1)
reached = threading.Event()


def feedback(fb):
    print("feedback: %d" % fb.current_number, flush=True)
    if fb.current_number >= 2:
        reached.set()


client.send_goal(CountGoal(count=30), feedback_cb=feedback)
reached.wait(60)
client.cancel_goal()
client.wait_for_result(rospy.Duration(30))
print(
    "state %d (PREEMPTED is %d), final_count %d"
    % (client.get_state(), actionlib.GoalStatus.PREEMPTED, client.get_result().final_count),
    flush=True,
)
