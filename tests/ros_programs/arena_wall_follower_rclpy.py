"""A wrong wall follower (rclpy): it follows the arena's wall, not the obstacle. It turns away from
the nearest thing (the obstacle), drives to the wall it then faces and keeps that wall on its
right, 0.4 m away. Graded, it fails: too long outside the band around the obstacle
(tests/e2e/test_grade_wall.py)."""

import math

import rclpy
from geometry_msgs.msg import Twist
from rclpy.node import Node
from sensor_msgs.msg import LaserScan

DISTANCE = 0.40


def nearest(ranges, first, last):
    best = (math.inf, (first + last) // 2)
    for i in range(first, last + 1):
        r = ranges[i % len(ranges)]
        if math.isfinite(r) and r < best[0]:
            best = (r, i)
    return best


class ArenaWall:
    """leave (turn until the way ahead is clear), cross (to the wall ahead), follow (wall on the right)."""

    def __init__(self):
        self.state = "leave"

    def command_for(self, ranges):
        front, _ = nearest(ranges, -20, 20)
        if self.state == "leave":
            if front > 1.2:
                self.state = "cross"
            return 0.0, 1.0
        if self.state == "cross":
            if front < DISTANCE + 0.15:
                self.state = "follow"
            return 0.15, 0.0
        right, index = nearest(ranges, 200, 340)
        if front < DISTANCE + 0.15:
            return 0.02, 1.2
        if right > 1.0:
            return 0.15, -0.6
        return 0.15, max(-1.5, min(1.5, -2.5 * (right - DISTANCE) + 1.5 * math.radians(index - 270)))


command_for = ArenaWall().command_for


class Follower(Node):
    def __init__(self):
        super().__init__("arena_wall_follower")
        self.publisher = self.create_publisher(Twist, "cmd_vel", 10)
        self.create_subscription(LaserScan, "scan", self.on_scan, 10)
        self.logic = ArenaWall()

    def on_scan(self, scan):
        msg = Twist()
        msg.linear.x, msg.angular.z = self.logic.command_for(scan.ranges)
        self.publisher.publish(msg)


def main():
    rclpy.init()
    node = Follower()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass


if __name__ == "__main__":
    main()
