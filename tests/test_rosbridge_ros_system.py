"""What ROS clients expect of a ROS system (issue 27, item 7), with roslibpy (unchanged) and raw
rosbridge frames against a real `hri-lab serve`: ROS 1's parameter server beside the declared
ROS 2 parameters, /rosout, /tf and /tf_static, service_response with `result: false`, actions
provided by clients, remote nodes' parameters."""
import json
import threading

import httpx
import pytest
import roslibpy

from app.cli.launch import running_server
from tests.waiting import wait_for


@pytest.fixture(scope="module")
def lab():
    with running_server("--view", "none") as server:
        yield server


@pytest.fixture(scope="module")
def ros(lab):
    client = roslibpy.Ros("127.0.0.1", lab.port, transport="asyncio")
    client.run()
    yield client
    client.close()
    client.terminate()


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
    assert [n for n in ros.get_params() if n.startswith("/robot")] == ["/robot/a/b"]
    roslibpy.Param(ros, "/robot").delete(timeout=30)
    assert not [n for n in ros.get_params() if n.startswith("/robot")]


def test_param_ros1_name_of_a_declared_parameter_is_that_parameter(ros, lab):
    mu = roslibpy.Param(ros, "/cooperative_lifting/mu")
    assert mu.get(timeout=30) == httpx.get(f"{lab.url}/params/cooperative_lifting/mu").json()["value"]
    mu.set(0.7, timeout=30)
    assert httpx.get(f"{lab.url}/params/cooperative_lifting/mu").json()["value"] == 0.7
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
        talker.publish(roslibpy.Message({"header": {"stamp": {"secs": 5, "nsecs": 0}}, "level": 4, "name": "/talker",
                                         "msg": "careful", "file": "talker.py", "function": "main", "line": 7}))
        line = ros2_inbox.wait(lambda m: m["name"] == "/talker")
        assert (line["level"], line["msg"], line["stamp"], line["line"]) == (30, "careful", {"sec": 5, "nanosec": 0}, 7)
        line1 = ros1_inbox.wait(lambda m: m["name"] == "/talker")
        assert (line1["level"], line1["header"]["stamp"]["secs"]) == (4, 5)
        # the lab's own lines: a service call answered, the lifting started
        assert httpx.post(f"{lab.url}/services/add_two_ints", json={"a": 1, "b": 2}).json()["sum"] == 3
        ros2_inbox.wait(lambda m: m["name"] == "service" and "/add_two_ints answered by the lab" in m["msg"]
                        and m["level"] == 10)
        # the console's filters (GET /log)
        warned = httpx.get(f"{lab.url}/log", params={"node": "/talker", "level": "WARN"}).json()
        assert [x["msg"] for x in warned] == ["careful"]
        assert httpx.get(f"{lab.url}/log", params={"node": "/talker", "level": "ERROR"}).json() == []
        assert httpx.get(f"{lab.url}/log", params={"level": "LOUD"}).status_code == 422
        talker.unadvertise()
    finally:
        other.close()
        other.terminate()


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

    echo = subprocess.Popen([sys.executable, "-m", "app.cli", "topic", "echo", "/rosout", "--count", "1", "--url", lab.url],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        def printed():  # log lines until the echo, once connected, has printed one
            httpx.post(f"{lab.url}/services/add_two_ints", json={"a": 2, "b": 2})
            return echo.poll() is not None

        wait_for(printed, 60)
        out = echo.stdout.read()
        assert echo.returncode == 0, echo.stderr.read()
        assert "name: service" in out and "level: 10" in out and "/add_two_ints answered" in out
    finally:
        if echo.poll() is None:
            echo.kill()
        echo.wait()
        echo.stdout.close()
        echo.stderr.close()
