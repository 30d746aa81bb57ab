"""A wrong wall follower (rclpy): it drives straight ahead whatever the scan says. Graded, it fails
on a collision (tests/e2e/test_grade_wall.py)."""

import rclpy
from geometry_msgs.msg import Twist
from rclpy.node import Node


class Straight(Node):
    def __init__(self):
        super().__init__("straight")
        self.publisher = self.create_publisher(Twist, "cmd_vel", 10)
        self.create_timer(0.1, self.tick)

    def tick(self):
        msg = Twist()
        msg.linear.x = 0.15
        self.publisher.publish(msg)


def main():
    rclpy.init()
    node = Straight()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass


if __name__ == "__main__":
    main()
