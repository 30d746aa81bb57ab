"""A string echo service (rclpy), the lab's hri_lab/Echo: out = in (a Python keyword: in_)."""

import rclpy
from hri_lab.srv import Echo
from rclpy.node import Node


def main():
    rclpy.init()
    node = Node("echo_server")

    def echo(request, response):
        response.out = request.in_
        return response

    node.create_service(Echo, "/echo", echo)
    node.get_logger().info("echo ready")
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass


if __name__ == "__main__":
    main()
