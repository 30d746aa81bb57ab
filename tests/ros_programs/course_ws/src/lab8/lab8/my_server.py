"""Lab 8's server (`ros2 run lab8 myServer`): /add_two_ints of example_interfaces, its offset a
parameter; main() with no `if __name__ == "__main__":` block, as setup.py's entry point calls it."""

import rclpy
from example_interfaces.srv import AddTwoInts
from rclpy.node import Node


class MyServer(Node):
    def __init__(self):
        super().__init__("my_server")
        self.declare_parameter("offset", 0)
        self.create_service(AddTwoInts, "add_two_ints", self.add)
        self.get_logger().info("myServer ready, offset %d" % self.get_parameter("offset").value)

    def add(self, request, response):
        response.sum = request.a + request.b + self.get_parameter("offset").value
        return response


def main(args=None):
    rclpy.init(args=args)
    node = MyServer()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
    node.destroy_node()
    rclpy.try_shutdown()
