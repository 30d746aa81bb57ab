"""Exercise 16's check, shared by the lifting node tests (tests/e2e/test_lifting_node.py: the roslibpy
node; tests/e2e/test_ros_lifting_node.py: the rospy program): lifting started through the lab's
service (the node answers it), the calm participant's carry watched to its end over HTTP."""

import time

import numpy as np

from tests.http_client import http
from tests.waiting import wait_provided


def position(url, topic):
    p = http.get(f"{url}/topics/{topic}").json()["pose"]["position"]
    return np.array([p["x"], p["y"], p["z"]])


def palm_in_box(url):
    """The palm's position in the box frame (m): how far the box slid in the person's hand."""
    box = http.get(f"{url}/topics/object_pose").json()["pose"]
    x, y, z, w = (box["orientation"][k] for k in "xyzw")
    rotation = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )
    return rotation.T @ (position(url, "human_hand_pose") - np.array([box["position"][k] for k in "xyz"]))


def slow_commands(url) -> None:
    """The command period raised to 5 s: the test machine is shared, and a starved node is not what
    these tests are about (tests/sim/controllers/test_external.py and test_rosbridge_roslibpy.py test
    the 100 ms watchdog)."""
    assert http.put(f"{url}/params/sim/command_period", json={"value": 5.0}).json()["successful"]


def carry_the_box(url, answer_ends: str, timeout_s: float) -> float:
    """Starts lifting with 10 N (the node's answer ends with `answer_ends`), waits at most `timeout_s`
    for the person's path to end, and checks the box was carried 0.30 m along -x, held between plate
    and palm, with the node as the controller. Returns how far the box slid in the palm (m)."""
    wait_provided(url, "/start_cooperative_lifting")  # by the node: the lab's own answers in the same words
    started = http.post(f"{url}/services/start_cooperative_lifting", json={"force": 10}, timeout=10).json()
    assert started["message"].endswith(answer_ends)  # the node's answer
    box_start = position(url, "object_pose")
    grasped = palm_in_box(url)
    state, deadline, slip = {}, time.monotonic() + timeout_s, 0.0
    while time.monotonic() < deadline:
        state = http.get(f"{url}/topics/lifting_state").json()
        slip = max(slip, float(np.linalg.norm(palm_in_box(url) - grasped)))
        if state["human_phase"] == "done" or state["error"]:
            break
        time.sleep(0.1)
    assert state["error"] == "" and state["human_phase"] == "done", state
    assert (position(url, "object_pose") - box_start)[0] < -0.25  # the 0.30 m carry along -x
    contact = http.get(f"{url}/topics/contact_state").json()
    assert contact["robot_contact"] and contact["human_contact"], f"dropped; slid {slip * 100:.1f} cm first"
    assert http.get(f"{url}/params/cooperative_lifting/controller").json()["value"] == "node"
    return slip
