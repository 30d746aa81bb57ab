"""bench/ros_programs.py's subscriber (run with `hri-lab run`): F_ext into a rospy callback with
queue_size=1 for SECONDS s; prints one JSON line: how many messages the lab published over the span
of simulation time seen (1 per ms), how many reached the program, how many the callback."""

import json
import sys
import time

import rospy
from geometry_msgs.msg import WrenchStamped

seen = {"first": None, "last": None, "handled": 0}


def callback(msg):
    stamp = msg.header.stamp.to_nsec()
    if seen["first"] is None:
        seen["first"] = stamp
    seen["last"] = stamp
    seen["handled"] += 1
    time.sleep(0.0002)  # a little work per message, as a controller does


rospy.init_node("fext_listener")
subscriber = rospy.Subscriber("/franka_state_controller/F_ext", WrenchStamped, callback, queue_size=1)
rospy.sleep(float(sys.argv[1]) if len(sys.argv) > 1 else 10.0)
subscriber.unregister()
published = round((seen["last"] - seen["first"]) / 1e6) + 1 if seen["first"] is not None else 0
print(json.dumps({"published": published, "arrived": subscriber.received, "handled": seen["handled"]}), flush=True)
