"""bench/camera.py's node (run with `hri-lab run`): /image_raw into a rospy callback that converts it
with cv_bridge, as the detection exercise does, for SECONDS s; prints one JSON line: each image's
arrival (wall clock, s) and stamp (simulated time, s)."""

import json
import sys
import time

import rospy
from cv_bridge import CvBridge
from sensor_msgs.msg import Image

bridge = CvBridge()
arrivals = []


def callback(msg):
    arrived = time.time()
    bridge.imgmsg_to_cv2(msg, "bgr8")
    arrivals.append((arrived, msg.header.stamp.to_sec()))


rospy.init_node("image_listener")
subscriber = rospy.Subscriber("/image_raw", Image, callback, queue_size=1)
while not arrivals and not rospy.is_shutdown():  # the renderer's start (a second or two)
    rospy.sleep(0.05)
del arrivals[:]
rospy.sleep(float(sys.argv[1]) if len(sys.argv) > 1 else 10.0)
subscriber.unregister()
print(json.dumps({"arrivals": arrivals}), flush=True)
