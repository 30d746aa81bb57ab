"""Call the lab's services from Python, as `ros2 service call` does.

Start the lab first (`make run`), then: python examples/01_call_a_service.py
"""

import os

import httpx

url = os.environ.get("HRI_LAB_URL", "http://127.0.0.1:8000")

with httpx.Client(base_url=url, timeout=10.0) as lab:
    # the service's definition, as `ros2 interface show` prints it
    print(lab.get("/services/add_two_ints").json()["srv"])
    print("sum:", lab.post("/services/add_two_ints", json={"a": 2, "b": 40}).json()["sum"])

    # a bad request is refused with the field it is about
    refused = lab.post("/services/add_two_ints", json={"a": "two", "b": 40})
    print("refused:", refused.status_code, refused.json()["detail"][0]["loc"][-1])

    # start cooperative lifting at 10 N, read the lifting state, stop
    print(lab.post("/services/start_cooperative_lifting", json={"force": 10.0}).json()["message"])
    state = lab.get("/topics/lifting_state").json()
    print(f"band: [{state['f_n_min']:g}, {state['f_n_max']:g}] N, started: {state['started']}")
    print(lab.post("/services/stop_cooperative_lifting").json()["message"])
