#!/usr/bin/env python
"""The camera exercise's detection node (rospy), as the handout writes it: image_raw through
cv_bridge, an HSV threshold for saturated bright colours, the largest contour's bounding
rectangle, its centre served as get_target_position; the image shown with cv2.imshow."""

import cv2
import numpy as np
import rospy
from cv_bridge import CvBridge
from hri_lab.srv import GetObjectPosition, GetObjectPositionResponse
from sensor_msgs.msg import Image


class ObjectDetector:
    def __init__(self):
        self.bridge = CvBridge()
        self.x = 0
        self.y = 0
        rospy.Subscriber("image_raw", Image, self.image_callback, queue_size=1)
        rospy.Service("get_target_position", GetObjectPosition, self.handle_get)

    def image_callback(self, msg):
        image = self.bridge.imgmsg_to_cv2(msg, "bgr8")
        hsv = cv2.cvtColor(image, cv2.COLOR_BGR2HSV)
        lower = np.array([0, 120, 80])
        upper = np.array([180, 255, 255])
        mask = cv2.inRange(hsv, lower, upper)
        contours, _ = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
        if contours:
            largest = max(contours, key=cv2.contourArea)
            x, y, w, h = cv2.boundingRect(largest)
            self.x = x + w // 2
            self.y = y + h // 2
            cv2.rectangle(image, (x, y), (x + w, y + h), (0, 0, 255), 2)
            cv2.circle(image, (self.x, self.y), 4, (0, 0, 255), -1)
        cv2.imshow("detection", image)
        cv2.waitKey(1)

    def handle_get(self, req):
        if not req.get:
            return GetObjectPositionResponse(0, 0)
        rospy.loginfo("target at (%d, %d)", self.x, self.y)
        return GetObjectPositionResponse(self.x, self.y)


if __name__ == "__main__":
    rospy.init_node("object_detector")
    detector = ObjectDetector()
    print("detector ready", flush=True)
    rospy.spin()
