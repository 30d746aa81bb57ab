#!/usr/bin/env python3
"""The camera handout's ROS 2 image server, as the handout prints it: an `ImageSubscriber` node that
subscribes `image_raw` (depth 10), finds the box with OpenCV, shows it with cv2.imshow and
cv2.waitKey(50) and serves its centre as `get_target_position`. Every image takes the callback more
than 50 ms, slower than the camera's 30 images/s: the service must still be answered."""

import cv2
import numpy as np
import rclpy
from cv_bridge import CvBridge
from hri_lab.srv import GetObjectPosition
from rclpy.node import Node
from sensor_msgs.msg import Image


class ImageSubscriber(Node):
    def __init__(self):
        super().__init__("image_subscriber")
        self.subscription = self.create_subscription(Image, "image_raw", self.listener_callback, 10)
        self.srv = self.create_service(GetObjectPosition, "get_target_position", self.get_target_position_callback)
        self.br = CvBridge()
        self.target_x = 0
        self.target_y = 0

    def listener_callback(self, data):
        self.get_logger().info("Receiving video frame")
        current_frame = self.br.imgmsg_to_cv2(data, "bgr8")
        hsv = cv2.cvtColor(current_frame, cv2.COLOR_BGR2HSV)
        mask = cv2.inRange(hsv, np.array([0, 120, 80]), np.array([180, 255, 255]))
        contours, _ = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
        if contours:
            x, y, w, h = cv2.boundingRect(max(contours, key=cv2.contourArea))
            self.target_x = x + w // 2
            self.target_y = y + h // 2
            cv2.rectangle(current_frame, (x, y), (x + w, y + h), (0, 0, 255), 2)
        cv2.imshow("camera", current_frame)
        cv2.waitKey(50)

    def get_target_position_callback(self, request, response):
        response.x = self.target_x
        response.y = self.target_y
        self.get_logger().info(f"Target position: ({response.x}, {response.y})")
        return response


def main(args=None):
    rclpy.init(args=args)
    image_subscriber = ImageSubscriber()
    rclpy.spin(image_subscriber)
    image_subscriber.destroy_node()
    rclpy.shutdown()


if __name__ == "__main__":
    main()
