"""Stream F_ext (/franka_state_controller/F_ext, geometry_msgs/WrenchStamped) over a WebSocket,
as `ros2 topic echo` does, while the robot presses the box.

Start the lab first (`make run`), then: python examples/02_stream_f_ext.py
"""

import json
import os

import httpx
from websockets.sync.client import connect

url = os.environ.get("HRI_LAB_URL", "http://127.0.0.1:8000")
httpx.post(f"{url}/services/start_cooperative_lifting", json={"force": 10.0}, timeout=10.0)

with connect(url.replace("http", "ws", 1) + "/topics/franka_state_controller/F_ext/stream?rate=20") as stream:
    for _ in range(40):  # two seconds at 20 Hz
        message = json.loads(stream.recv())
        stamp = message["header"]["stamp"]
        force = message["wrench"]["force"]
        print(f"t = {stamp['sec'] + stamp['nanosec'] * 1e-9:7.3f} s   f_n = F.z = {force['z']:6.2f} N")

httpx.post(f"{url}/services/stop_cooperative_lifting", timeout=10.0)
