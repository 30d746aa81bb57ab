"""The lab's services over HTTP against the real app and its live loop."""

import math

import numpy as np
import pytest

from sim.robot import planar_arm

from app.lab import commands as cmd
from tests.waiting import wait_for, wait_sim

EXPECTED = {
    "/start_cooperative_lifting": "hri_lab/StartCooperativeLifting",
    "/stop_cooperative_lifting": "hri_lab/StopCooperativeLifting",
    "/compute_torques": "hri_lab/ComputeTorques",
    "/compute_wrench": "hri_lab/ComputeWrench",
    "/planar_torques": "hri_lab/PlanarTorques",
    "/add_two_ints": "hri_lab/AddTwoInts",
    "/divide_ints": "hri_lab/DivideInts",
    "/multiply_three": "hri_lab/MultiplyThree",
    "/echo": "hri_lab/Echo",
    "/login": "hri_lab/Login",
    "/get_target_position": "hri_lab/GetObjectPosition",
    "/error_recovery": "std_srvs/Trigger",
    "/reset_simulation": "std_srvs/Trigger",
    "/start_recording": "hri_lab/StartRecording",
    "/stop_recording": "hri_lab/StopRecording",
}


def refused(response, field):
    """422 whose error names `field`."""
    assert response.status_code == 422, response.text
    locs = [e["loc"] for e in response.json()["detail"]]
    assert any(field in loc for loc in locs), locs


def test_service_list_and_types(client):
    listed = {s["name"]: s["type"] for s in client.get("/services").json()}
    assert listed == EXPECTED


def test_service_definitions(client):
    start = client.get("/services/start_cooperative_lifting").json()
    assert (
        start["srv"] == "float64 force\nstring controller  # '' keeps the current one; sp or patch\n---\nstring message"
    )
    assert client.get("/services/error_recovery").json()["srv"] == "---\nbool success\nstring message"
    assert client.get("/services/echo").json()["srv"] == "string in\n---\nstring out"
    assert (
        client.get("/services/planar_torques").json()["srv"] == "float64[] q\nfloat64[] force\n---\nfloat64[] torques"
    )
    assert client.get("/services/nope").status_code == 404
    # each service is a typed route in the OpenAPI schema
    paths = client.get("/openapi.json").json()["paths"]
    assert "requestBody" in paths["/services/add_two_ints"]["post"]


def test_start_moves_the_robot_to_the_box_and_stop_zeroes_the_command(client, lab):
    client.post("/services/reset_simulation")
    response = client.post("/services/start_cooperative_lifting", json={"force": 10.0})
    assert response.status_code == 200
    assert "10" in response.json()["message"]
    state = client.get("/topics/lifting_state").json()
    assert (state["started"], state["f_n_min"], state["f_n_max"]) == (True, 10.0, 15.0)
    assert lab.call(cmd.lifting_state)[1::2] == (10.0, 15.0)
    # the robot approaches: F_ext f_z rises within a few hundred ms of real time
    fz = wait_for(
        lambda: (f := client.get("/topics/franka_state_controller/F_ext").json()["wrench"]["force"]["z"]) > 5 and f
    )
    assert fz > 5
    command = client.get("/topics/cartesian_velocity_controller/command").json()
    assert command["linear"]["y"] >= 0.0  # pressing along the plate normal (base +y)
    response = client.post("/services/stop_cooperative_lifting")
    assert "stopped" in response.json()["message"]
    assert "0" in response.json()["message"]

    def command_is_zero():
        c = client.get("/topics/cartesian_velocity_controller/command").json()
        return all(abs(v) < 1e-9 for part in ("linear", "angular") for v in c[part].values())

    wait_for(command_is_zero, timeout=2.0)
    assert client.get("/topics/lifting_state").json()["started"] is False


@pytest.mark.parametrize(
    "body", [{"force": -1.0}, {"force": 61.0}, {"force": "10"}, {"force": "NaN"}, {"force": None}, {}]
)
def test_start_refusals(client, body):
    refused(client.post("/services/start_cooperative_lifting", json=body), "force")


@pytest.mark.parametrize(
    "raw", [b'{"force": NaN}', b'{"force": Infinity}', b'{"force": 1e999}', b'{"force": -Infinity}']
)
def test_start_refuses_non_finite_numbers(client, raw):
    response = client.post(
        "/services/start_cooperative_lifting", content=raw, headers={"content-type": "application/json"}
    )
    refused(response, "force")


def test_compute_torques(client, lab):
    client.post("/services/stop_cooperative_lifting")
    wait_for(lambda: np.abs(lab.snapshot().qdot).max() < 1e-4)  # at rest (but for the posture term fading out)
    force = np.array([1.0, -2.0, 3.0, 0.1, 0.2, -0.3])
    q_before = lab.snapshot().q
    torques = client.post("/services/compute_torques", json={"force": force.tolist()}).json()["torques"]
    q_after = lab.snapshot().q  # the robot may still creep (posture term): tau at a q in between
    assert len(torques) == 7
    before, after = (lab.model.jacobian_base(q).T @ force for q in (q_before, q_after))
    assert torques == pytest.approx(before, abs=1e-6 + np.abs(after - before).max())
    refused(client.post("/services/compute_torques", json={"force": [1.0] * 5}), "force")
    refused(client.post("/services/compute_torques", json={"force": [1.0] * 7}), "force")
    refused(client.post("/services/compute_torques", json={"force": [1, 2, 3, 4, 5, "NaN"]}), "force")
    refused(client.post("/services/compute_torques", json={"force": "123456"}), "force")
    # huge but finite inputs whose result overflows: a failure response, not a 500 (found by fuzzing)
    overflow = client.post("/services/compute_wrench", json={"torques": [1.7e308] * 7})
    assert overflow.status_code == 400
    assert "overflows" in overflow.json()["detail"]


def test_compute_wrench_round_trip(client, lab):
    wrench = np.array([2.0, 0.5, -1.0, 0.1, 0.0, 0.2])
    q_before = lab.snapshot().q
    tau = lab.model.torques_from_wrench(q_before, wrench)
    body = client.post("/services/compute_wrench", json={"torques": tau.tolist()}).json()
    q_after = lab.snapshot().q  # the robot may still creep (posture term): F at a q in between
    after = lab.model.wrench_from_torques(q_after, tau)[0]
    assert body["force"] == pytest.approx(wrench, abs=1e-6 + np.abs(after - wrench).max())
    assert "residual" in body["message"]
    refused(client.post("/services/compute_wrench", json={"torques": [0.0] * 6}), "torques")


def test_planar_torques(client):
    body = client.post(
        "/services/planar_torques", json={"q": [math.pi / 2, -math.pi / 2, math.pi / 2], "force": [1.0, 0.0]}
    ).json()
    assert body["torques"] == pytest.approx([-2.0, -1.0, -1.0])
    assert client.post("/services/planar_torques", json={"q": [0, 0, 0], "force": [0, 1, 0.5]}).json()[
        "torques"
    ] == pytest.approx(planar_arm.torques([0, 0, 0], [0, 1, 0.5]))
    refused(client.post("/services/planar_torques", json={"q": [0, 0], "force": [1, 0]}), "q")
    refused(client.post("/services/planar_torques", json={"q": [0, 0, 0], "force": [1]}), "force")


def test_integer_services(client):
    assert client.post("/services/add_two_ints", json={"a": 2, "b": 3}).json() == {"sum": 5}
    assert client.post("/services/divide_ints", json={"a": 7, "b": 2}).json() == {
        "result": 3.5,
        "message": "Division ok.",
    }
    assert client.post("/services/divide_ints", json={"a": 7, "b": 0}).json() == {
        "result": 0.0,
        "message": "Division by zero!",
    }
    assert client.post("/services/multiply_three", json={"a": 2, "b": 3, "c": -4}).json() == {"product": -24}
    # int64 is int64: an input beyond it is refused, a result beyond it is a clear failure
    refused(client.post("/services/add_two_ints", json={"a": 2**63, "b": 0}), "a")
    refused(client.post("/services/add_two_ints", json={"a": 1.5, "b": 0}), "a")
    refused(client.post("/services/add_two_ints", json={"a": True, "b": 0}), "a")
    refused(client.post("/services/add_two_ints", json={"a": "1", "b": 0}), "a")
    refused(client.post("/services/add_two_ints", json={"a": 1}), "b")
    overflow = client.post("/services/multiply_three", json={"a": 2**62, "b": 2, "c": 2})
    assert overflow.status_code == 400
    assert "int64" in overflow.json()["detail"]
    overflow = client.post("/services/add_two_ints", json={"a": 2**63 - 1, "b": 1})
    assert overflow.status_code == 400
    assert "int64" in overflow.json()["detail"]


def test_echo_login_and_camera(client):
    assert client.post("/services/echo", json={"in": "hello lab"}).json() == {"out": "hello lab"}
    refused(client.post("/services/echo", json={}), "in")
    refused(client.post("/services/echo", json={"in": "x", "extra": 1}), "extra")
    ok = client.post("/services/login", json={"username": "ada", "magic_number": 42}).json()
    assert ok["success"] is True
    assert "ada" in ok["message"]
    assert client.post("/services/login", json={"username": "ada", "magic_number": 7}).json()["success"] is False
    pixel = client.post("/services/get_target_position", json={"get": True}).json()
    assert 0 <= pixel["x"] < 640
    assert 0 <= pixel["y"] < 480
    assert client.post("/services/get_target_position", json={"get": False}).json() == {"x": 0, "y": 0}
    assert any(line["node"] == "get_target_position" for line in client.get("/log").json())
    refused(client.post("/services/get_target_position", json={"get": "yes"}), "get")


def test_camera_projection_follows_the_box():
    """The projection by hand: a point on the optical axis lands in the image centre; a point
    higher up lands above it (smaller y)."""
    from sim.camera import CAMERA_TARGET, project

    assert project(CAMERA_TARGET) == (320, 240)
    x, y = project(CAMERA_TARGET + [0.0, 0.0, 0.1])
    assert x == 320
    assert y < 240


def _too_fast(world) -> None:
    world.arm.command_twist(np.array([0.0, 0.0, 5.0, 0, 0, 0]), 1e-3)  # 5 m/s: a reflex


def test_error_recovery_and_reset(client, lab):
    lab.call(_too_fast)
    assert "cartesian velocity limit" in client.get("/topics/lifting_state").json()["error"]
    body = client.post("/services/error_recovery").json()
    assert body["success"] is True
    assert "cartesian velocity limit" in body["message"]
    assert client.get("/topics/lifting_state").json()["error"] == ""
    assert client.post("/services/error_recovery").json()["message"] == "No error to recover from."
    client.post("/services/start_cooperative_lifting", json={"force": 10.0})
    body = client.post("/services/reset_simulation").json()
    assert body["success"] is True
    assert "lifting stopped" in body["message"]
    state = client.get("/topics/lifting_state").json()
    assert (state["human_phase"], state["started"], state["f_n_min"]) == ("grasping", False, 0.0)
    wait_sim(lab.snapshot, 0.5)  # the person waits: no grip in a band, so no release
    assert client.get("/topics/lifting_state").json()["human_phase"] == "grasping"


def test_a_thousand_bad_requests_never_give_a_5xx(client, lab):
    rng = np.random.default_rng(0)
    junk = [
        None,
        True,
        -1,
        2**64,
        -(2**70),
        1.5,
        1e308,
        "",
        "x" * 100,
        "NaN",
        [],
        [1, "a"],
        {},
        {"a": 1},
        [float(v) for v in range(6)],
        [1e308] * 7,
    ]
    names = list(EXPECTED)
    for _ in range(1000):
        name = names[rng.integers(len(names))]
        body = {
            str(
                rng.choice(["a", "b", "c", "force", "torques", "q", "in", "get", "username", "magic_number", "zz"])
            ): junk[rng.integers(len(junk))]
            for _ in range(rng.integers(0, 4))
        }
        value = junk[rng.integers(len(junk))]
        kind = rng.random()
        if kind < 0.1:
            response = client.post(
                f"/services{name}",
                content=bytes(rng.integers(0, 256, 20).tolist()),
                headers={"content-type": "application/json"},
            )
        elif kind < 0.2:  # parameters: any node/name, any value
            node, param = (
                rng.choice(["cooperative_lifting", "sim", "human", "keytwist", "nope"]),
                rng.choice(["f_n_min", "mu", "rate_hz", "profile", "box_mass", "linear_speed", "nope"]),
            )
            response = client.put(f"/params/{node}/{param}", json={"value": value})
        elif kind < 0.25:
            response = client.post(
                "/params/load",
                content=bytes(rng.integers(0, 256, 30).tolist()),
                headers={"content-type": "application/yaml"},
            )
        elif kind < 0.3:  # action goals with junk (a goal that passes is cancelled at once)
            response = client.post("/actions/count/goals", json=body)
            if response.status_code == 202:
                client.post(f"/actions/count/goals/{response.json()['goal_id']}/cancel")
        else:
            response = client.post(f"/services{name}", json=body)
        assert response.status_code < 500, (name, body, response.text)
    assert lab.runtime.health().alive
    assert client.get("/health").json()["loop_alive"] is True


def test_topic_stream_delivers_at_about_the_asked_rate(client):
    with client.websocket_connect("/topics/franka_state_controller/F_ext/stream?rate=50") as ws:
        first = ws.receive_json()
        start_stamp = first["header"]["stamp"]["sec"] + first["header"]["stamp"]["nanosec"] * 1e-9
        count, previous, gaps = 0, start_stamp, []
        while True:
            msg = ws.receive_json()
            count += 1
            stamp = msg["header"]["stamp"]["sec"] + msg["header"]["stamp"]["nanosec"] * 1e-9
            gaps.append(stamp - previous)
            previous = stamp
            if stamp - start_stamp >= 1.0:
                break
    # never more than the asked rate: each message at least one period (20 ms) of simulated time after
    # the one before (how many fewer a loaded machine delivers depends on its speed: not asserted)
    assert min(gaps) >= 0.02 - 0.0005 and count <= 51, (count, min(gaps))
    assert msg["header"]["frame_id"] == "panda_K"
    assert "force" in msg["wrench"]


def test_topic_stream_refusals(client):
    from starlette.websockets import WebSocketDisconnect

    for path in ("/topics/nope/stream", "/topics/joint_states/stream?rate=0", "/topics/joint_states/stream?rate=5000"):
        with pytest.raises(WebSocketDisconnect), client.websocket_connect(path) as ws:
            ws.receive_json()


def _break_human(world) -> None:
    def broken(*args, **kwargs):
        raise ValueError("injected fault")

    world.human.step = broken


def _fix_human(world) -> None:
    del world.human.step  # back to the class's method


def test_a_simulation_fault_stops_the_robot_not_the_loop(client, lab):
    """A bug inside a step (here: the human model raising) puts the robot in an error state; the
    loop keeps ticking and answers; once fixed, error_recovery clears it."""
    lab.call(_break_human)
    wait_for(lambda: lab.runtime.health().stats.step_errors > 10)
    health = client.get("/health").json()
    assert health["loop_alive"] is True
    assert health["step_errors"] > 10
    assert "simulation error: ValueError: injected fault" in client.get("/topics/lifting_state").json()["error"]
    lab.call(_fix_human)
    assert client.post("/services/error_recovery").json()["success"] is True
    ticks = lab.runtime.health().stats.ticks
    wait_for(lambda: lab.runtime.health().stats.ticks > ticks + 100)
    assert client.get("/topics/lifting_state").json()["error"] == ""


def test_start_selects_the_controller(client, lab):
    """The start service's `controller` selects sp or patch before starting; '' keeps the current one."""
    client.post("/services/stop_cooperative_lifting")
    assert (
        client.post("/services/start_cooperative_lifting", json={"force": 10, "controller": "patch"}).status_code == 200
    )
    assert lab.call(cmd.controller_name) == "PatchController"
    assert lab.call(cmd.lifting_state)[:2] == (True, 10.0)
    assert client.get("/params/cooperative_lifting/controller").json()["value"] == "patch"
    client.post("/services/stop_cooperative_lifting")
    client.post("/services/start_cooperative_lifting", json={"force": 12})
    assert lab.call(cmd.controller_name) == "PatchController"  # kept
    refused = client.post("/services/start_cooperative_lifting", json={"force": 12, "controller": "pid"})
    assert refused.status_code == 422
    assert refused.json()["detail"][0]["loc"][-1] == "controller"
    client.post("/services/start_cooperative_lifting", json={"force": 10, "controller": "sp"})
    assert lab.call(cmd.controller_name) == "SPController"
    client.post("/services/stop_cooperative_lifting")
