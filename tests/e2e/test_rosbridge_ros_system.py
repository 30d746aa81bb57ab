"""What ROS clients expect of a ROS system (issue 27, item 7), with roslibpy (unchanged) and raw
rosbridge frames against a real `hri-lab serve`: ROS 1's parameter server beside the declared
ROS 2 parameters, /rosout, /tf and /tf_static, service_response with `result: false`, actions
provided by clients, remote nodes' parameters."""

import json
import threading

import pytest
import roslibpy

from tests.e2e.serving import served_lab
from tests.http_client import http
from tests.waiting import wait_for

lab = served_lab()


def rosapi(ros, service, **args):
    return roslibpy.Service(ros, f"/rosapi/{service}", "rosapi/X").call(roslibpy.ServiceRequest(args), timeout=30)


# --- ROS 1's parameter server ------------------------------------------------------------------
def test_param_any_name_set_read_deleted(ros):
    param = roslibpy.Param(ros, "test_param")
    assert param.get(timeout=30) is None  # ROS 1's rosapi: an unset name reads as null
    param.set("test_value", timeout=30)
    assert param.get(timeout=30) == "test_value"
    assert "/test_param" in ros.get_params()
    param.delete(timeout=30)
    assert param.get(timeout=30) is None
    assert "/test_param" not in ros.get_params()


def test_param_namespaces_search_and_has(ros):
    roslibpy.Param(ros, "/robot/arm/gain").set(2.5, timeout=30)
    roslibpy.Param(ros, "/robot/arm/name").set("panda", timeout=30)
    assert roslibpy.Param(ros, "/robot/arm").get(timeout=30) == {"gain": 2.5, "name": "panda"}
    assert rosapi(ros, "has_param", name="/robot/arm/gain")["exists"] is True
    assert rosapi(ros, "has_param", name="/robot/leg")["exists"] is False
    assert rosapi(ros, "search_param", name="robot")["global_name"] == "/robot"
    assert rosapi(ros, "search_param", name="nowhere")["global_name"] == ""
    roslibpy.Param(ros, "/robot").set({"a": {"b": [1, 2]}}, timeout=30)  # a dict replaces the subtree
    assert [n for n in ros.get_params() if n.startswith("/robot/")] == ["/robot/a/b"]
    roslibpy.Param(ros, "/robot").delete(timeout=30)
    assert not [n for n in ros.get_params() if n.startswith("/robot/")]


def test_param_ros1_name_of_a_declared_parameter_is_that_parameter(ros, lab):
    mu = roslibpy.Param(ros, "/cooperative_lifting/mu")
    assert mu.get(timeout=30) == http.get(f"{lab.url}/params/cooperative_lifting/mu").json()["value"]
    mu.set(0.7, timeout=30)
    assert http.get(f"{lab.url}/params/cooperative_lifting/mu").json()["value"] == 0.7
    with pytest.raises(roslibpy.core.ServiceException, match=r"Wrong parameter type, parameter \{mu\}"):
        mu.set("slippery", timeout=30)  # typed as declared
    with pytest.raises(roslibpy.core.ServiceException, match="declared"):
        mu.delete(timeout=30)
    mu.set(0.5, timeout=30)
    assert roslibpy.Param(ros, "/cooperative_lifting").get(timeout=30)["mu"] == 0.5  # the node's namespace


def test_param_bad_values_refused_with_reason(ros):
    with pytest.raises(roslibpy.core.ServiceException, match="JSON"):
        rosapi(ros, "set_param", name="/x", value="not json")
    with pytest.raises(roslibpy.core.ServiceException, match="number"):
        rosapi(ros, "set_param", name="/x", value="NaN")
    with pytest.raises(roslibpy.core.ServiceException, match="ROS name"):
        rosapi(ros, "set_param", name="/bad name!", value="1")


# --- /rosout -----------------------------------------------------------------------------------
class Inbox:
    """Messages of a roslibpy subscription, waited on with a bound."""

    def __init__(self, ros, topic, type_name):
        self.messages, self.lock = [], threading.Lock()
        self.topic = roslibpy.Topic(ros, topic, type_name)
        self.topic.subscribe(self.take)

    def take(self, message):
        with self.lock:
            self.messages.append(message)

    def wait(self, predicate, timeout=30.0):
        def found():
            with self.lock:
                return next((m for m in self.messages if predicate(m)), None)

        return wait_for(found, timeout)


def test_rosout_listed_and_carries_nodes_lines_in_both_types(ros, lab):
    assert "/rosout" in ros.get_topics()
    assert ros.get_topic_type("/rosout") == "rcl_interfaces/Log"
    ros2_inbox = Inbox(ros, "/rosout", "rcl_interfaces/Log")
    other = roslibpy.Ros("127.0.0.1", lab.port, transport="asyncio")
    other.run()
    try:
        ros1_inbox = Inbox(other, "/rosout", "rosgraph_msgs/Log")  # a ROS 1 client reads ROS 1's type
        talker = roslibpy.Topic(other, "/rosout", "rosgraph_msgs/Log")
        talker.advertise()
        wait_for(lambda: "/rosout" in ros.get_node_details(other_name(ros, other))["publishing"])
        talker.publish(
            roslibpy.Message(
                {
                    "header": {"stamp": {"secs": 5, "nsecs": 0}},
                    "level": 4,
                    "name": "/talker",
                    "msg": "careful",
                    "file": "talker.py",
                    "function": "main",
                    "line": 7,
                }
            )
        )
        line = ros2_inbox.wait(lambda m: m["name"] == "/talker")
        assert (line["level"], line["msg"], line["stamp"], line["line"]) == (30, "careful", {"sec": 5, "nanosec": 0}, 7)
        line1 = ros1_inbox.wait(lambda m: m["name"] == "/talker")
        assert (line1["level"], line1["header"]["stamp"]["secs"]) == (4, 5)
        # the lab's own lines: a service call answered, the lifting started
        assert http.post(f"{lab.url}/services/add_two_ints", json={"a": 1, "b": 2}).json()["sum"] == 3
        ros2_inbox.wait(
            lambda m: m["name"] == "service" and "/add_two_ints answered by the lab" in m["msg"] and m["level"] == 10
        )
        # the console's filters (GET /log)
        warned = http.get(f"{lab.url}/log", params={"node": "/talker", "level": "WARN"}).json()
        assert [x["msg"] for x in warned] == ["careful"]
        assert http.get(f"{lab.url}/log", params={"node": "/talker", "level": "ERROR"}).json() == []
        assert http.get(f"{lab.url}/log", params={"level": "LOUD"}).status_code == 422
        talker.unadvertise()
    finally:
        other.close()  # (terminate() would stop the event loop roslibpy's clients share)


def other_name(ros, other):
    """The rosbridge node name of client `other` (the newest client the lab lists)."""
    return ros.get_nodes()[-1]


def test_rosout_refuses_wrong_types_and_levels(lab):
    import websockets.sync.client

    with websockets.sync.client.connect(f"ws://127.0.0.1:{lab.port}/") as ws:
        ws.send(json.dumps({"op": "advertise", "topic": "/rosout", "type": "std_msgs/String"}))
        assert "rcl_interfaces/Log" in json.loads(ws.recv(timeout=30))["msg"]
        ws.send(json.dumps({"op": "advertise", "topic": "/rosout", "type": "rcl_interfaces/msg/Log"}))
        ws.send(json.dumps({"op": "publish", "topic": "/rosout", "msg": {"level": 4, "msg": "x"}}))  # ROS 1's number
        assert "field 'level' must be one of [10, 20, 30, 40, 50]" in json.loads(ws.recv(timeout=30))["msg"]


def test_topic_echo_rosout_cli(lab):
    import subprocess
    import sys

    echo = subprocess.Popen(
        [sys.executable, "-m", "app.cli", "topic", "echo", "/rosout", "--count", "1", "--url", lab.url],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:

        def printed():  # log lines until the echo, once connected, has printed one
            http.post(f"{lab.url}/services/add_two_ints", json={"a": 2, "b": 2})
            return echo.poll() is not None

        wait_for(printed, 60)
        out = echo.stdout.read()
        assert echo.returncode == 0, echo.stderr.read()
        assert "name: service" in out
        assert "level: 10" in out
        assert "/add_two_ints answered" in out
    finally:
        if echo.poll() is None:
            echo.kill()
        echo.wait()
        echo.stdout.close()
        echo.stderr.close()


# --- /tf, /tf_static, /republish_tfs -------------------------------------------------------------
def test_tf_client_reads_frames_through_republish_tfs(ros, lab):
    """roslibpy's TFClient (unchanged): identity for the fixed frame, the flange where franka_states has it."""
    from roslibpy.tf import TFClient

    client = TFClient(ros, fixed_frame="world")
    got = {}
    done = {name: threading.Event() for name in ("world", "panda_link8")}

    def keep(name):
        def callback(transform):
            got[name] = transform
            done[name].set()

        return callback

    client.subscribe(frame_id="/world", callback=keep("world"))
    client.subscribe(frame_id="panda_link8", callback=keep("panda_link8"))
    assert all(event.wait(30) for event in done.values())
    assert got["world"] == {
        "translation": {"x": 0.0, "y": 0.0, "z": 0.0},
        "rotation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0},
    }
    o_t_ee = http.get(f"{lab.url}/topics/franka_state_controller/franka_states").json()["O_T_EE"]  # column-major 4x4
    flange = got["panda_link8"]["translation"]
    assert [flange["x"], flange["y"], flange["z"]] == pytest.approx(o_t_ee[12:15], abs=1e-6)  # the robot is still
    with pytest.raises(roslibpy.core.ServiceException, match="frame 'nowhere' does not exist"):
        roslibpy.Service(ros, "/republish_tfs", "tf2_web_republisher/RepublishTFs").call(
            roslibpy.ServiceRequest({"source_frames": ["nowhere"], "target_frame": "world", "rate": 10.0}), timeout=30
        )


def test_tf_and_tf_static_topics(ros, lab):
    static, moving = Inbox(ros, "/tf_static", "tf2_msgs/TFMessage"), Inbox(ros, "/tf", "tf2_msgs/TFMessage")
    message = static.wait(lambda m: True)
    edges = {(t["header"]["frame_id"], t["child_frame_id"]): t["transform"] for t in message["transforms"]}
    assert edges[("panda_link8", "plate")]["translation"] == {"x": 0.0, "y": 0.0, "z": 0.02}  # plate_offset
    assert ("world", "panda_link0") in edges
    assert ("panda_hand", "panda_leftfinger") in edges
    tf_message = moving.wait(lambda m: True)
    children = {t["child_frame_id"]: t["header"]["frame_id"] for t in tf_message["transforms"]}
    assert children == {
        **{f"panda_link{i}": f"panda_link{i - 1}" for i in range(1, 8)},
        "box": "panda_link0",
        "palm": "panda_link0",
    }

    def stamp(m):
        return m["transforms"][0]["header"]["stamp"]["sec"] + m["transforms"][0]["header"]["stamp"]["nanosec"] * 1e-9

    # /tf goes on over half a second of simulation (several /tf_static periods); /tf_static (latched) was sent once
    wait_for(lambda: len(moving.messages) >= 2 and stamp(moving.messages[-1]) - stamp(moving.messages[0]) >= 0.5)
    assert len(static.messages) == 1
    static.topic.unsubscribe()
    moving.topic.unsubscribe()
    assert {"/tf", "/tf_static"} <= set(ros.get_topics())
    assert "/republish_tfs" in ros.get_services()


# --- service_response with result: false ---------------------------------------------------------
def test_service_response_result_false_still_delivers_values(ros, lab):
    """As rosbridge_suite's service_response (what roslibpy's servers were tested against): the
    values are the response; values that are no response make a failed call with them as the reason."""

    def add(request, response):
        response["sum"] = request["a"] + request["b"]
        return False  # roslibpy's ros1 test_service does this

    def refuse(request, response):
        response["error"] = "no such thing"
        return False

    server = roslibpy.Service(ros, "/false_sum", "rospy_tutorials/AddTwoInts")
    server.advertise(add)
    refusing = roslibpy.Service(ros, "/false_refuse", "rospy_tutorials/AddTwoInts")
    refusing.advertise(refuse)
    wait_for(lambda: {"/false_sum", "/false_refuse"} <= set(ros.get_services()))
    try:
        assert (
            roslibpy.Service(ros, "/false_sum", "rospy_tutorials/AddTwoInts").call(
                roslibpy.ServiceRequest({"a": 2, "b": 40}), timeout=30
            )["sum"]
            == 42
        )
        answer = http.post(f"{lab.url}/services/false_sum", json={"a": 1, "b": 1}, timeout=30)
        assert (answer.status_code, answer.json()) == (200, {"sum": 2})
        refused = http.post(f"{lab.url}/services/false_refuse", json={"a": 1, "b": 1}, timeout=30)
        assert refused.status_code == 400
        assert "no such thing" in refused.json()["detail"]
    finally:
        server.unadvertise()
        refusing.unadvertise()


# --- actions provided by clients ------------------------------------------------------------------
class CountingServer:
    """A client that provides /counting (a student's own type counting_pkg/Counting: int32 target ---
    int32 final --- int32 current) over raw rosbridge frames, as rosbridge_suite's protocol has it:
    counts to the goal, one feedback per number, stops on cancel_action_goal with status 5."""

    def __init__(self, port, name="/counting", step_s=0.05):
        import websockets.sync.client

        self.name, self.step_s = name, step_s
        self.ws = websockets.sync.client.connect(f"ws://127.0.0.1:{port}/")
        self.lock = threading.Lock()
        self.canceled: dict[str, threading.Event] = {}
        self.goals: list[dict] = []
        self.send({"op": "advertise_action", "action": name, "type": "counting_pkg/action/Counting"})
        self.reader = threading.Thread(target=self.read, daemon=True)
        self.reader.start()

    def send(self, message):
        with self.lock:
            try:
                self.ws.send(json.dumps(message))
            except Exception:  # noqa: BLE001 - closed: the node is gone (what the test makes happen)
                pass

    def read(self):
        try:
            for text in self.ws:
                message = json.loads(text)
                if message["op"] == "send_action_goal":
                    self.goals.append(message)
                    self.canceled[message["id"]] = threading.Event()
                    threading.Thread(target=self.count, args=(message,), daemon=True).start()
                elif message["op"] == "cancel_action_goal":
                    self.canceled[message["id"]].set()
        except Exception:  # noqa: BLE001 - the socket closed
            pass

    def count(self, goal):
        current = 0
        for current in range(1, goal["args"]["target"] + 1):
            if self.canceled[goal["id"]].wait(self.step_s):
                self.send(
                    {
                        "op": "action_result",
                        "id": goal["id"],
                        "action": self.name,
                        "values": {"final": current - 1},
                        "status": 5,
                        "result": True,
                    }
                )
                return
            self.send({"op": "action_feedback", "id": goal["id"], "action": self.name, "values": {"current": current}})
        self.send(
            {
                "op": "action_result",
                "id": goal["id"],
                "action": self.name,
                "values": {"final": current},
                "status": 4,
                "result": True,
            }
        )

    def close(self):
        self.ws.close()
        self.reader.join(timeout=10)


def goal_view(lab, name, goal_id, after=0):
    return http.get(f"{lab.url}/actions{name}/goals/{goal_id}", params={"after": after, "wait": 5}, timeout=30).json()


def wait_goal(lab, name, goal_id, status):
    def reached():
        view = goal_view(lab, name, goal_id)
        return view if view["status"] == status else None

    return wait_for(reached, 60)


@pytest.fixture
def counting(lab):
    server = CountingServer(lab.port)
    wait_for(lambda: any(a["name"] == "/counting" for a in http.get(f"{lab.url}/actions").json()))
    yield server
    server.close()


def test_client_action_listed_and_served_over_http(lab, ros, counting):
    assert {"name": "/counting", "type": "counting_pkg/action/Counting"} in http.get(f"{lab.url}/actions").json()
    assert "/counting" in rosapi(ros, "action_servers")["action_servers"]
    sent = http.post(f"{lab.url}/actions/counting/goals", json={"target": 3}, timeout=30)
    assert sent.status_code == 202, sent.text
    view = wait_goal(lab, "/counting", sent.json()["goal_id"], "succeeded")
    assert view["result"] == {"final": 3}
    assert view["feedback"] == [{"current": 1}, {"current": 2}, {"current": 3}]
    assert counting.goals[-1]["args"] == {"target": 3}
    assert counting.goals[-1]["action_type"] == "counting_pkg/action/Counting"


def test_client_action_preempted_over_http_and_goals_run_side_by_side(lab, counting):
    goal_id = http.post(f"{lab.url}/actions/counting/goals", json={"target": 100000}, timeout=30).json()["goal_id"]
    wait_for(lambda: goal_view(lab, "/counting", goal_id)["feedback_count"] >= 1)
    # a second goal goes to the node too (rosbridge_suite forwards every goal; the node's server decides)
    second = http.post(f"{lab.url}/actions/counting/goals", json={"target": 1}, timeout=30)
    assert second.status_code == 202, second.text
    assert wait_goal(lab, "/counting", second.json()["goal_id"], "succeeded")["result"] == {"final": 1}
    assert goal_view(lab, "/counting", goal_id)["status"] == "active"
    canceled = http.post(f"{lab.url}/actions/counting/goals/{goal_id}/cancel", timeout=30).json()
    assert canceled["status"] in ("preempting", "preempted")
    view = wait_goal(lab, "/counting", goal_id, "preempted")
    assert view["result"]["final"] >= 1  # what the node had counted, its canceled result


def test_client_action_goal_from_cli_and_from_another_client(lab, ros, counting):
    import subprocess
    import sys

    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "app.cli",
            "action",
            "send_goal",
            "/counting",
            "{target: 2}",
            "--feedback",
            "--url",
            lab.url,
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 0, out.stdout + out.stderr
    assert "current: 2" in out.stdout
    assert "final: 2" in out.stdout
    assert "SUCCEEDED" in out.stdout
    client = roslibpy.ActionClient(ros, "/counting", "counting_pkg/action/Counting")
    results, feedbacks = [], []
    goal_id = client.send_goal(roslibpy.Goal({"target": 2}), results.append, feedbacks.append, results.append)
    client.wait_goal(goal_id, 60)
    assert results[0]["values"] == {"final": 2}
    assert results[0]["status"].value == 4
    assert [f["current"] for f in feedbacks] == [1, 2]


def test_client_action_goes_with_its_node_and_its_goal_aborts(lab):
    server = CountingServer(lab.port, step_s=0.2)
    wait_for(lambda: any(a["name"] == "/counting" for a in http.get(f"{lab.url}/actions").json()))
    goal_id = http.post(f"{lab.url}/actions/counting/goals", json={"target": 100000}, timeout=30).json()["goal_id"]
    wait_for(lambda: goal_view(lab, "/counting", goal_id)["status"] == "active")
    server.close()
    view = wait_goal(lab, "/counting", goal_id, "aborted")
    assert "withdrew action /counting" in view["message"]
    wait_for(lambda: all(a["name"] != "/counting" for a in http.get(f"{lab.url}/actions").json()))
    assert http.post(f"{lab.url}/actions/counting/goals", json={"target": 1}, timeout=30).status_code == 404


def test_advertise_action_refusals(lab):
    import websockets.sync.client

    with websockets.sync.client.connect(f"ws://127.0.0.1:{lab.port}/") as ws:
        ws.send(json.dumps({"op": "advertise_action", "action": "/count", "type": "hri_lab/Count"}))
        assert "action /count is the lab's" in json.loads(ws.recv(timeout=30))["msg"]
        ws.send(
            json.dumps(
                {"op": "action_result", "id": "nope", "action": "/counting", "values": {}, "status": 4, "result": True}
            )
        )
        assert "no goal with id nope" in json.loads(ws.recv(timeout=30))["msg"]


# --- parameters of a node, through its standard parameter services ---------------------------------
class ParamNode:
    """A client node `/keytwist_param` declaring linear_speed (double in [0, 5]) and angular_speed,
    serving rcl_interfaces' parameter services over raw rosbridge frames as rclpy does; its
    on-set check refuses linear_speed above 4 with a reason."""

    def __init__(self, port, node="/keytwist_param"):
        import websockets.sync.client

        self.node = node
        self.values = {"linear_speed": 0.1, "angular_speed": 0.5}
        self.ws = websockets.sync.client.connect(f"ws://127.0.0.1:{port}/")
        self.lock = threading.Lock()
        for service, type_ in (
            ("get_parameters", "GetParameters"),
            ("set_parameters", "SetParameters"),
            ("list_parameters", "ListParameters"),
            ("describe_parameters", "DescribeParameters"),
        ):
            self.send(
                {"op": "advertise_service", "service": f"{node}/{service}", "type": f"rcl_interfaces/srv/{type_}"}
            )
        self.reader = threading.Thread(target=self.read, daemon=True)
        self.reader.start()

    def send(self, message):
        with self.lock:
            try:
                self.ws.send(json.dumps(message))
            except Exception:  # noqa: BLE001 - closed
                pass

    def read(self):
        try:
            for text in self.ws:
                message = json.loads(text)
                if message["op"] == "call_service":
                    values = self.serve(message["service"].rsplit("/", 1)[1], message["args"])
                    self.send(
                        {
                            "op": "service_response",
                            "id": message["id"],
                            "service": message["service"],
                            "values": values,
                            "result": True,
                        }
                    )
        except Exception:  # noqa: BLE001 - the socket closed
            pass

    def serve(self, service, args):
        if service == "list_parameters":
            return {"result": {"names": sorted(self.values), "prefixes": []}}
        if service == "get_parameters":
            return {
                "values": [
                    {"type": 3, "double_value": self.values[n]} if n in self.values else {"type": 0}
                    for n in args["names"]
                ]
            }
        if service == "describe_parameters":
            return {
                "descriptors": [
                    {
                        "name": n,
                        "type": 3,
                        "description": f"{n} (m/s)" if n == "linear_speed" else n,
                        "read_only": False,
                        "floating_point_range": [{"from_value": 0.0, "to_value": 5.0, "step": 0.0}],
                        "integer_range": [],
                    }
                    for n in args["names"]
                ]
            }
        results = []
        for parameter in args["parameters"]:
            value = parameter["value"]
            if value["type"] != 3:
                results.append(
                    {
                        "successful": False,
                        "reason": f"Wrong parameter type, parameter {{{parameter['name']}}} is of type {{double}}",
                    }
                )
            elif parameter["name"] == "linear_speed" and value["double_value"] > 4.0:
                results.append({"successful": False, "reason": "linear_speed must be <= 4.0"})
            else:
                self.values[parameter["name"]] = value["double_value"]
                results.append({"successful": True, "reason": ""})
        return {"results": results}

    def close(self):
        self.ws.close()
        self.reader.join(timeout=10)


def cli(lab, *args):
    import subprocess
    import sys

    return subprocess.run(
        [sys.executable, "-m", "app.cli", *args, "--url", lab.url], capture_output=True, text=True, timeout=120
    )


def test_node_parameters_in_the_labs_registry(lab, ros):
    node = ParamNode(lab.port)
    try:
        wait_for(lambda: any(p["node"] == "keytwist_param" for p in http.get(f"{lab.url}/params", timeout=30).json()))
        listed = {(p["node"], p["name"]): p for p in http.get(f"{lab.url}/params", timeout=30).json()}
        assert listed[("keytwist_param", "linear_speed")]["value"] == 0.1
        assert listed[("cooperative_lifting", "mu")]["type"] == "double"  # the lab's own stay
        out = cli(lab, "param", "set", "/keytwist_param", "linear_speed", "3.5")
        assert out.returncode == 0 and "Set parameter successful" in out.stdout, out.stdout + out.stderr
        assert node.values["linear_speed"] == 3.5  # the running node has it
        assert "3.5" in cli(lab, "param", "get", "/keytwist_param", "linear_speed").stdout
        refused = cli(lab, "param", "set", "/keytwist_param", "linear_speed", "4.5")
        assert refused.returncode != 0
        assert "Setting parameter failed: linear_speed must be <= 4.0" in refused.stdout
        assert (
            cli(lab, "param", "set", "/keytwist_param", "angular_speed", "2").returncode == 0
        )  # an integer, sent as double
        assert node.values["angular_speed"] == 2.0
        described = http.get(f"{lab.url}/params/keytwist_param/linear_speed/describe", timeout=30).json()
        assert (described["type"], described["min_value"], described["max_value"]) == ("double", 0.0, 5.0)
        assert "linear_speed (m/s)" in cli(lab, "param", "describe", "/keytwist_param", "linear_speed").stdout
        assert "keytwist_param:" in cli(lab, "param", "dump", "/keytwist_param").stdout
        assert "/keytwist_param:linear_speed" in ros.get_params()
        assert ros.get_param("/keytwist_param:linear_speed") == 3.5
        ros.set_param("/keytwist_param:linear_speed", 1.5)
        assert node.values["linear_speed"] == 1.5
        with pytest.raises(roslibpy.core.ServiceException, match=r"linear_speed must be <= 4.0"):
            ros.set_param("/keytwist_param:linear_speed", 9.0)
    finally:
        node.close()
    wait_for(lambda: all(p["node"] != "keytwist_param" for p in http.get(f"{lab.url}/params", timeout=30).json()))
    assert http.get(f"{lab.url}/params/keytwist_param/linear_speed", timeout=30).status_code == 404
