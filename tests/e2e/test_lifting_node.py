"""Exercise 16 in the live lab: the lifting node from the template (filled in with the SP law)
carries the calm participant's box, driving the robot only through rosbridge (F_ext in, Twist
commands out). Real time: ~20 s. The command period is raised to 5 s here: the test machine is
shared, and a starved node is not what this test is about (tests/sim/controllers/test_external.py and
test_rosbridge_roslibpy.py test the 100 ms watchdog)."""

import subprocess
import sys
import time
from pathlib import Path

import httpx
import numpy as np

from app.cli.launch import running_server

NODE = Path(__file__).resolve().parents[1] / "nodes" / "lifting_solution.py"


def position(url, topic):
    p = httpx.get(f"{url}/topics/{topic}").json()["pose"]["position"]
    return np.array([p["x"], p["y"], p["z"]])


def palm_in_box(url):
    """The palm's position in the box frame (m): how far the box slid in the person's hand."""
    box = httpx.get(f"{url}/topics/object_pose").json()["pose"]
    x, y, z, w = (box["orientation"][k] for k in "xyzw")
    rotation = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )
    return rotation.T @ (position(url, "human_hand_pose") - np.array([box["position"][k] for k in "xyz"]))


def test_the_lifting_node_carries_the_box():
    with running_server("--view", "none") as lab:
        assert httpx.put(f"{lab.url}/params/sim/command_period", json={"value": 5.0}).json()["successful"]
        node = subprocess.Popen(
            [sys.executable, str(NODE), "--port", str(lab.port)],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
        )
        try:
            assert node.stdout.readline().startswith("node ready")
            started = httpx.post(f"{lab.url}/services/start_cooperative_lifting", json={"force": 10}, timeout=10).json()
            assert started["message"].endswith("f_n_max = 15 N.")  # the node's answer
            box_start = position(lab.url, "object_pose")
            grasped = palm_in_box(lab.url)
            state, deadline, slip = {}, time.monotonic() + 120, 0.0
            while time.monotonic() < deadline:
                state = httpx.get(f"{lab.url}/topics/lifting_state").json()
                slip = max(slip, float(np.linalg.norm(palm_in_box(lab.url) - grasped)))
                if state["human_phase"] == "done" or state["error"]:
                    break
                time.sleep(0.1)
            assert state["error"] == "" and state["human_phase"] == "done", state
            carried = position(lab.url, "object_pose") - box_start
            assert carried[0] < -0.25  # the 0.30 m carry along -x
            contact = httpx.get(f"{lab.url}/topics/contact_state").json()
            # held between plate and palm to the end: carried, not dropped. How far the box slid in the
            # palm on the way depends on how promptly the node's process gets a core (the built-in SP
            # at 1 kHz: 4 mm; a node on a loaded 2-core machine: 3.5-9 cm), so it is reported, not asserted
            assert contact["robot_contact"] and contact["human_contact"], f"dropped; slid {slip * 100:.1f} cm first"
            assert httpx.get(f"{lab.url}/params/cooperative_lifting/controller").json()["value"] == "node"
        finally:
            node.terminate()
            node.wait(timeout=10)
            node.stdout.close()
