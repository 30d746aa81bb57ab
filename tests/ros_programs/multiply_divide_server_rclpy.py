"""MultiplyThree and DivideInts servers (rclpy) with the workspace's own cpp_package/srv files."""

import rclpy
from cpp_package.srv import DivideInts, MultiplyThree
from rclpy.node import Node


class Calculator(Node):
    def __init__(self):
        super().__init__("calculator")
        self.create_service(MultiplyThree, "multiply_three", self.multiply)
        self.create_service(DivideInts, "divide_ints", self.divide)
        self.get_logger().info("calculator ready")

    def multiply(self, request, response):
        response.product = request.a * request.b * request.c
        return response

    def divide(self, request, response):
        if request.b == 0:
            response.result = 0.0
            response.message = "Division by zero!"
        else:
            response.result = request.a / request.b
            response.message = "Division ok."
        return response


def main():
    rclpy.init()
    node = Calculator()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        print("calculator stopped by Ctrl+C", flush=True)
    node.destroy_node()
    rclpy.try_shutdown()


if __name__ == "__main__":
    main()
