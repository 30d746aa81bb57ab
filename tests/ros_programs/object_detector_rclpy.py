#!/usr/bin/env python3
"""The camera exercise's detection node (rclpy), as the ROS 2 handout writes it: image_raw through
cv_bridge, an HSV threshold, the largest contour's bounding rectangle, its centre served as
get_target_position."""

import cv2
import numpy as np
import rclpy
from cv_bridge import CvBridge
from hri_lab.srv import GetObjectPosition
from rclpy.node import Node
from sensor_msgs.msg import Image


class ObjectDetector(Node):
    def __init__(self):
        super().__init__("object_detector")
        self.bridge = CvBridge()
        self.x = 0
        self.y = 0
        self.create_subscription(Image, "image_raw", self.image_callback, 1)
        self.create_service(GetObjectPosition, "get_target_position", self.handle_get)

    def image_callback(self, msg):
        image = self.bridge.imgmsg_to_cv2(msg, desired_encoding="bgr8")
        hsv = cv2.cvtColor(image, cv2.COLOR_BGR2HSV)
        mask = cv2.inRange(hsv, np.array([40, 100, 80]), np.array([80, 255, 255]))  # green
        contours, _ = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
        if contours:
            x, y, w, h = cv2.boundingRect(max(contours, key=cv2.contourArea))
            self.x, self.y = x + w // 2, y + h // 2

    def handle_get(self, request, response):
        if request.get:
            response.x, response.y = self.x, self.y
        return response


def main():
    rclpy.init()
    node = ObjectDetector()
    print("detector ready", flush=True)
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
    node.destroy_node()


if __name__ == "__main__":
    main()
