#!/usr/bin/env python
"""The counting action (actionlib, the workspace's cpp_package/Counting.action): counts to the goal,
one number per ~delay (default 1 s), with feedback; a preempt stops it."""

import actionlib
import rospy
from cpp_package.msg import CountingAction, CountingFeedback, CountingResult


class Counter:
    def __init__(self):
        self.delay = rospy.get_param("~delay", 1.0)
        self.server = actionlib.SimpleActionServer("counting", CountingAction, self.execute, auto_start=False)
        self.server.start()

    def execute(self, goal):
        current = 0
        while current < goal.count:
            if self.server.is_preempt_requested():
                rospy.loginfo("counting preempted at %d", current)
                self.server.set_preempted(CountingResult(reached=current))
                return
            rospy.sleep(self.delay)
            current += 1
            self.server.publish_feedback(CountingFeedback(current=current))
        self.server.set_succeeded(CountingResult(reached=current))


if __name__ == "__main__":
    rospy.init_node("counting_server")
    Counter()
    rospy.loginfo("counting server ready")
    rospy.spin()
