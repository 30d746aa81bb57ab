#!/usr/bin/env python
"""actionlib_tutorials' `fibonacci_server` (its C++ node, which roslibjs's test setup,
test/examples/setup_examples.launch, starts) as a rospy program: a SimpleActionServer named after
the node, `/fibonacci`, that appends `order` numbers to the seeds 0, 1 at 1 Hz with a feedback each,
so order 7 gives [0, 1, 1, 2, 3, 5, 8, 13, 21] as roslibjs's test expects (the tutorial's Python
server appends one fewer). Its messages are actionlib_tutorials' (`--workspace` the corpus's
ros/common_tutorials folder)."""

import actionlib
import rospy
from actionlib_tutorials.msg import FibonacciAction, FibonacciFeedback, FibonacciResult


class FibonacciServer:
    def __init__(self, name: str) -> None:
        self.name = name
        self.server = actionlib.SimpleActionServer(name, FibonacciAction, execute_cb=self.execute, auto_start=False)
        self.server.start()

    def execute(self, goal) -> None:
        rate = rospy.Rate(1)
        feedback = FibonacciFeedback(sequence=[0, 1])
        rospy.loginfo("%s: Executing, creating fibonacci sequence of order %i with seeds 0, 1", self.name, goal.order)
        for i in range(1, goal.order + 1):
            if self.server.is_preempt_requested() or rospy.is_shutdown():
                rospy.loginfo("%s: Preempted", self.name)
                self.server.set_preempted()
                return
            feedback.sequence.append(feedback.sequence[i] + feedback.sequence[i - 1])
            self.server.publish_feedback(feedback)
            rate.sleep()
        rospy.loginfo("%s: Succeeded", self.name)
        self.server.set_succeeded(FibonacciResult(sequence=feedback.sequence))


if __name__ == "__main__":
    rospy.init_node("fibonacci")
    FibonacciServer(rospy.get_name())
    rospy.spin()
