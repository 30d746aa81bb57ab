"""Calls a service no program provides yet (in `serve --exercises`): the future holds the exception."""

import time

import rclpy
from hri_lab.srv import DivideInts

rclpy.init()
node = rclpy.create_node("divider")
future = node.create_client(DivideInts, "/divide_ints").call_async(DivideInts.Request(a=7, b=2))
time.sleep(1.0)  # the lab's answer has come meanwhile, but it completes the future only inside spin
print("done before spin: %s" % future.done(), flush=True)
rclpy.spin_until_future_complete(node, future, timeout_sec=30)
print("done: %s, exception: %s" % (future.done(), future.exception()), flush=True)
rclpy.shutdown()
