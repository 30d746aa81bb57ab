"""bench/ros_programs.py's caller (run with `hri-lab run`): a rospy program that calls another
program's /add_two_ints N times, one at a time, through rospy.ServiceProxy; prints one JSON line
with each call's round trip (ms)."""

import json
import sys
import time

import rospy
from example_interfaces.srv import AddTwoInts

rospy.init_node("add_two_ints_caller")
rospy.wait_for_service("add_two_ints", timeout=60)
add = rospy.ServiceProxy("add_two_ints", AddTwoInts)
for i in range(20):  # warm-up
    add(i, 1)
latencies = []
for i in range(int(sys.argv[1]) if len(sys.argv) > 1 else 300):
    t0 = time.perf_counter()
    answer = add(i, 1)
    latencies.append((time.perf_counter() - t0) * 1e3)
    assert answer.sum == i + 1, answer
print(json.dumps({"latencies_ms": latencies}), flush=True)
