#!/usr/bin/env python3
"""ros2/examples' client that runs a coroutine on the executor: `executor.create_task(call_service)`,
where call_service awaits `client.call_async` twice (the second request uses the first answer)."""

import sys

import rclpy
from example_interfaces.srv import AddTwoInts
from rclpy.executors import SingleThreadedExecutor


async def call_service(node, client, a, b):
    request = AddTwoInts.Request()
    request.a, request.b = a, b
    first = await client.call_async(request)
    node.get_logger().info("Result of add_two_ints: for %d + %d = %d" % (a, b, first.sum))
    request = AddTwoInts.Request(a=first.sum, b=b)
    second = await client.call_async(request)
    node.get_logger().info("Result of add_two_ints: for %d + %d = %d" % (first.sum, b, second.sum))
    return second.sum


def main(args=None):
    with rclpy.init(args=args):
        node = rclpy.create_node("minimal_client_async_task")
        client = node.create_client(AddTwoInts, "add_two_ints")
        while not client.wait_for_service(timeout_sec=1.0):
            node.get_logger().info("service not available, waiting again...")
        executor = SingleThreadedExecutor()
        executor.add_node(node)
        task = executor.create_task(call_service, node, client, int(sys.argv[1]), int(sys.argv[2]))
        executor.spin_until_future_complete(task, timeout_sec=60.0)
        print("task done: %s, result %s" % (task.done(), task.result()), flush=True)


if __name__ == "__main__":
    main()
