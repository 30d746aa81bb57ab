"""AddTwoInts client (rclpy): adds the two numbers of its command line with the service."""

import sys

import rclpy
from example_interfaces.srv import AddTwoInts
from rclpy.node import Node


class MinimalClientAsync(Node):
    def __init__(self):
        super().__init__("minimal_client_async")
        self.cli = self.create_client(AddTwoInts, "add_two_ints")
        while not self.cli.wait_for_service(timeout_sec=1.0):
            self.get_logger().info("service not available, waiting again...")
        self.req = AddTwoInts.Request()

    def send_request(self, a, b):
        self.req.a = a
        self.req.b = b
        self.future = self.cli.call_async(self.req)


def main(args=None):
    rclpy.init(args=args)
    client = MinimalClientAsync()
    client.send_request(int(sys.argv[1]), int(sys.argv[2]))
    while rclpy.ok():  # the future completes inside spin_once
        rclpy.spin_once(client)
        if client.future.done():
            try:
                response = client.future.result()
            except Exception as e:
                client.get_logger().info("Service call failed %r" % (e,))
            else:
                print(
                    "Result of add_two_ints: for %d + %d = %d" % (client.req.a, client.req.b, response.sum), flush=True
                )
            break
    client.destroy_node()
    rclpy.shutdown()


if __name__ == "__main__":
    main()
