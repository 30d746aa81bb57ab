#!/usr/bin/env python
"""Prints every StudentInfo it receives on /student_info (rclpy)."""

import rclpy
from rclpy.node import Node
from student_pkg.msg import StudentInfo


class Listener(Node):
    def __init__(self):
        super().__init__("student_info_listener")
        self.create_subscription(StudentInfo, "student_info", self.heard, 100)

    def heard(self, msg):
        print(f"heard {msg.name} age {msg.age} marks {list(msg.marks)}", flush=True)


if __name__ == "__main__":
    rclpy.init()
    node = Listener()
    print("listener ready", flush=True)
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
