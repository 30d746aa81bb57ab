"""Exercise 16 in the live lab with a rospy program under `hri-lab run`: the lifting node
(tests/ros_programs/lifting_node_rospy.py) carries the calm participant's box, driving the robot
only through rosbridge (F_ext in, Twist commands out). As tests/e2e/test_lifting_node.py (the roslibpy
node), the command period is raised to 5 s: the test machine is shared."""

import time

import httpx
import numpy as np

from app.cli.launch import running_server
from tests.ros_running import run
from tests.e2e.test_lifting_node import palm_in_box, position


def test_the_rospy_lifting_node_carries_the_box():
    with running_server("--view", "none") as lab:
        assert httpx.put(f"{lab.url}/params/sim/command_period", json={"value": 5.0}).json()["successful"]
        node = run(lab.url, "lifting_node_rospy.py")
        try:
            node.wait_for_line("lifting node ready")
            started = httpx.post(f"{lab.url}/services/start_cooperative_lifting", json={"force": 10}, timeout=10).json()
            assert started["message"].endswith("f_n_max = 15 N")  # the program's answer
            box_start = position(lab.url, "object_pose")
            grasped = palm_in_box(lab.url)
            state, deadline, slip = {}, time.monotonic() + 180, 0.0
            while time.monotonic() < deadline:
                state = httpx.get(f"{lab.url}/topics/lifting_state").json()
                slip = max(slip, float(np.linalg.norm(palm_in_box(lab.url) - grasped)))
                if state["human_phase"] == "done" or state["error"]:
                    break
                time.sleep(0.1)
            assert state["error"] == "" and state["human_phase"] == "done", state
            assert (position(lab.url, "object_pose") - box_start)[0] < -0.25  # the 0.30 m carry along -x
            contact = httpx.get(f"{lab.url}/topics/contact_state").json()
            assert contact["robot_contact"] and contact["human_contact"]
            assert slip < 0.08, slip
            assert httpx.get(f"{lab.url}/params/cooperative_lifting/controller").json()["value"] == "node"
        finally:
            node.interrupt()
