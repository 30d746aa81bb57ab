#!/usr/bin/env python3
# -*- coding: utf-8 -*-
"""The course's adder server, as its handout writes it: a node with an AddTwoInts service of the
course's own interface package, and main() with no `if __name__ == "__main__":` block (setup.py's
entry point calls it: `ros2 run learning_service service_adder_server`)."""

import rclpy
from learning_interface.srv import AddTwoInts
from rclpy.node import Node


class adderServer(Node):
    def __init__(self, name):
        super().__init__(name)
        self.srv = self.create_service(AddTwoInts, "add_two_ints", self.adder_callback)

    def adder_callback(self, request, response):
        response.sum = request.a + request.b
        self.get_logger().info("Incoming request\na: %d b: %d" % (request.a, request.b))
        return response


def main(args=None):
    rclpy.init(args=args)
    node = adderServer("service_adder_server")
    node.get_logger().info("adder server ready")
    rclpy.spin(node)
    node.destroy_node()
    rclpy.shutdown()
