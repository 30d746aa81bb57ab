"""Parameters over HTTP: ROS 2 refusal messages, describe, dump/load round trip, live effect."""

from operator import attrgetter

import pytest
import yaml

from app.lab import commands as cmd
from tests.waiting import wait_sim

YAML = {"content-type": "application/yaml"}


def put(client, node, name, value):
    return client.put(f"/params/{node}/{name}", json={"value": value})


def test_list_get_describe(client):
    listed = {(p["node"], p["name"]): p for p in client.get("/params").json()}
    for key in [
        ("cooperative_lifting", "f_n_min"),
        ("cooperative_lifting", "mu"),
        ("keytwist", "linear_speed"),
        ("sim", "rate_hz"),
        ("sim", "box_mass"),
        ("human", "squeeze_force"),
        ("human", "profile"),
    ]:
        assert key in listed
    assert client.get("/params/keytwist/linear_speed").json()["value"] == 0.1
    d = client.get("/params/cooperative_lifting/f_n_min/describe").json()
    assert (d["type"], d["min_value"], d["max_value"], d["read_only"]) == ("double", 0.0, 60.0, False)
    assert client.get("/params/sim/rate_hz/describe").json()["read_only"] is True


@pytest.mark.parametrize(
    ("node", "name", "value", "status", "reason"),
    [
        (
            "cooperative_lifting",
            "mu",
            "high",
            422,
            "Wrong parameter type, parameter {mu} is of type {double}, setting it to {string} is not allowed.",
        ),
        (
            "cooperative_lifting",
            "mu",
            True,
            422,
            "Wrong parameter type, parameter {mu} is of type {double}, setting it to {bool} is not allowed.",
        ),
        ("sim", "rate_hz", 1.5, 422, "parameter 'rate_hz' cannot be set because it is read-only"),
        ("cooperative_lifting", "f_n_min", 61.0, 422, "Parameter {f_n_min} doesn't comply with floating point range."),
        ("cooperative_lifting", "f_n_min", -0.1, 422, "Parameter {f_n_min} doesn't comply with floating point range."),
        ("cooperative_lifting", "nope", 1.0, 404, "parameter 'nope' cannot be set because it was not declared"),
        ("human", "profile", "sleepy", 422, "Parameter {profile} must be one of calm, average, hasty, brisk, tilting."),
    ],
)
def test_refusals_keep_the_value(client, node, name, value, status, reason):
    before = client.get(f"/params/{node}/{name}").json().get("value")
    response = put(client, node, name, value)
    assert response.status_code == status
    assert response.json() == {"successful": False, "reason": reason}
    assert client.get(f"/params/{node}/{name}").json().get("value") == before


def test_non_finite_double_is_refused(client):
    response = client.put(
        "/params/cooperative_lifting/mu", content=b'{"value": NaN}', headers={"content-type": "application/json"}
    )
    assert response.status_code == 422
    assert response.json()["reason"] == "Parameter {mu} doesn't comply with floating point range."


def test_undeclared_get_and_describe(client):
    assert client.get("/params/cooperative_lifting/nope").json()["reason"] == "Parameter not set."
    assert client.get("/params/cooperative_lifting/nope/describe").status_code == 404


def test_set_reaches_the_running_simulation(client, lab):
    assert put(client, "cooperative_lifting", "k_t", 0.25).json() == {"successful": True, "reason": ""}
    assert lab.call(cmd.get_lifting, "k_t") == 0.25
    assert put(client, "sim", "box_mass", 2).json()["successful"] is True  # an integer for a double
    assert lab.call(attrgetter("box.params.mass")) == 2.0
    assert put(client, "human", "profile", "hasty").json()["successful"] is True
    assert lab.call(cmd.get_person, "name") == "hasty"
    put(client, "human", "profile", "calm")
    put(client, "sim", "box_mass", 1.0)
    put(client, "cooperative_lifting", "k_t", 0.1)


def test_a_changed_gain_changes_the_controller(client, lab):
    """k_n = 0: the started robot no longer approaches the box; k_n back: it does."""
    client.post("/services/reset_simulation")
    assert put(client, "cooperative_lifting", "k_n", 0.0).json()["successful"]
    client.post("/services/start_cooperative_lifting", json={"force": 10.0})
    wait_sim(lab.snapshot, 0.6)
    command = client.get("/topics/cartesian_velocity_controller/command").json()
    assert abs(command["linear"]["y"]) < 1e-9
    assert client.get("/topics/franka_state_controller/F_ext").json()["wrench"]["force"]["z"] < 3.0
    assert put(client, "cooperative_lifting", "k_n", 0.005).json()["successful"]
    wait_sim(lab.snapshot, 0.3)
    assert client.get("/topics/cartesian_velocity_controller/command").json()["linear"]["y"] > 0.0
    client.post("/services/stop_cooperative_lifting")


def test_controller_parameter_swaps_the_controller(client, lab):
    assert put(client, "cooperative_lifting", "controller", "patch").json()["successful"] is True
    assert lab.call(cmd.controller_name) == "PatchController"
    assert (
        put(client, "cooperative_lifting", "controller", "pid").json()["reason"]
        == "Parameter {controller} must be one of sp, patch."
    )
    assert put(client, "cooperative_lifting", "controller", "sp").json()["successful"] is True
    assert lab.call(cmd.controller_name) == "SPController"


def test_start_service_and_parameter_agree(client):
    client.post("/services/start_cooperative_lifting", json={"force": 12.5})
    assert client.get("/params/cooperative_lifting/f_n_min").json()["value"] == 12.5
    client.post("/services/stop_cooperative_lifting")
    assert client.get("/params/cooperative_lifting/f_n_min").json()["value"] == 0.0


def test_dump_load_round_trip(client):
    put(client, "keytwist", "linear_speed", 0.3)
    dump = client.get("/params/dump").text
    tree = yaml.safe_load(dump)
    assert tree["keytwist"]["ros__parameters"]["linear_speed"] == 0.3
    assert yaml.safe_load(client.get("/params/dump", params={"node": "sim"}).text).keys() == {"sim"}
    put(client, "keytwist", "linear_speed", 0.1)
    # load everything back: read-only rate_hz is refused, the rest is set
    body = client.post("/params/load", content=dump, headers=YAML).json()
    failures = {r["name"]: r["reason"] for r in body["results"] if not r["successful"]}
    assert failures == {"rate_hz": "parameter 'rate_hz' cannot be set because it is read-only"}
    assert client.get("/params/keytwist/linear_speed").json()["value"] == 0.3
    assert yaml.safe_load(client.get("/params/dump").text) == tree
    assert client.post("/params/load", content=b"{not: [yaml", headers=YAML).status_code == 422
    assert client.post("/params/load", content=b"- 1\n- 2\n", headers=YAML).status_code == 422
    put(client, "keytwist", "linear_speed", 0.1)
