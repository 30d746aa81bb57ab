#!/usr/bin/env python3
"""A node of the `greetings` package (ament_python): its service type is the package's own
(srv/SayHello.srv, found by the package.xml's name), its logic in the package's module."""

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node

from greetings.greeter import greeting
from greetings.srv import SayHello


class HelloServer(Node):
    def __init__(self):
        super().__init__("hello_server")
        self.srv = self.create_service(SayHello, "say_hello", self.say_hello)
        self.get_logger().info("hello server ready")

    def say_hello(self, request, response):
        response.greeting = greeting(request.name)
        return response


def main(args=None):
    try:
        with rclpy.init(args=args):
            rclpy.spin(HelloServer())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


if __name__ == "__main__":
    main()
