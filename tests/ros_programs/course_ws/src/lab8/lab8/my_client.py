"""Lab 8's client (`ros2 run lab8 myClient A B`): one call of /add_two_ints, its sum printed."""

import sys

import rclpy
from example_interfaces.srv import AddTwoInts
from rclpy.node import Node


def main(args=None):
    rclpy.init(args=args)
    node = Node("my_client")
    client = node.create_client(AddTwoInts, "add_two_ints")
    while not client.wait_for_service(timeout_sec=1.0):
        node.get_logger().info("service not available, waiting again...")
    request = AddTwoInts.Request()
    request.a, request.b = int(sys.argv[1]), int(sys.argv[2])
    future = client.call_async(request)
    rclpy.spin_until_future_complete(node, future)
    print("sum: %d" % future.result().sum, flush=True)
    node.destroy_node()
    rclpy.shutdown()
    return 0
