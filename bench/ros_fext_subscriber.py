"""bench/ros_programs.py's subscriber (run with `hri-lab run`): F_ext into a rospy callback with
queue_size=1 for SECONDS s (the callback: bench/fext_callback.py, computing WORK s a message, 0.2 ms
if not given); prints one JSON line: how many messages the lab published over the span of
simulation time seen (1 per ms), how many reached the program, how many the callback, how many
callbacks took longer than 1 ms, and how far behind the freshest the messages handled were.

    hri-lab run bench/ros_fext_subscriber.py [SECONDS] [WORK]"""

import json
import sys

import rospy
from geometry_msgs.msg import WrenchStamped

from bench.fext_callback import Tally

tally = Tally(float(sys.argv[2])) if len(sys.argv) > 2 else Tally()


def callback(msg):
    tally.handle(msg.header.stamp.to_nsec())


rospy.init_node("fext_listener")
subscriber = rospy.Subscriber("/franka_state_controller/F_ext", WrenchStamped, callback, queue_size=1)
rospy.sleep(float(sys.argv[1]) if len(sys.argv) > 1 else 10.0)
subscriber.unregister()
print(json.dumps({**tally.figures(), "arrived": subscriber.received}), flush=True)
