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
