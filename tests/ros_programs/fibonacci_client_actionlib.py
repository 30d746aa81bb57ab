#!/usr/bin/env python
"""actionlib_tutorials' Fibonacci client: a SimpleActionClient that waits for the result."""

from __future__ import print_function

import sys

import actionlib
import actionlib_tutorials.msg
import rospy


def fibonacci_client():
    client = actionlib.SimpleActionClient("fibonacci", actionlib_tutorials.msg.FibonacciAction)
    client.wait_for_server()
    goal = actionlib_tutorials.msg.FibonacciGoal(order=int(sys.argv[1]) if len(sys.argv) > 1 else 20)
    client.send_goal(goal)
    client.wait_for_result()
    return client.get_result()


if __name__ == "__main__":
    try:
        rospy.init_node("fibonacci_client_py")
        result = fibonacci_client()
        print("Result:", ", ".join([str(n) for n in result.sequence]))
    except rospy.ROSInterruptException:
        print("program interrupted before completion", file=sys.stderr)
