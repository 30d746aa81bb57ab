"""The mobile world's app in process: its page, its arena, the page's teleop (bad input is a 422
naming the field), its topics over HTTP (a scan's out-of-range rays as null)."""

import json
import math

import pytest
from fastapi.testclient import TestClient

from sim.mobile.playback import is_mobile
from sim.mobile.world import MobileConfig
from sim.recording import reader

from app.mobile.lab import MobileLab
from app.mobile.world import MOBILE
from app.serving.compose import create_app
from tests.waiting import wait_for


@pytest.fixture(scope="module")
def client():
    with TestClient(create_app(MOBILE, MobileLab(MobileConfig()))) as c:
        yield c


def test_the_page_and_the_arena(client):
    page = client.get("/")
    assert page.status_code == 200
    assert "the mobile world" in page.text
    arena = client.get("/mobile/arena").json()
    assert arena["half_size_xy"] == [2.0, 2.0]
    assert arena["obstacles"][0]["shape"] == "cylinder"
    assert arena["max_linear"] == 0.22
    assert arena["max_angular"] == 2.84
    names = {s["name"] for s in client.get("/services").json()}
    assert names == {"/start_recording", "/stop_recording"}  # the lifting lab's others are not this world's
    assert client.post("/teleop/key", json={"key": "w"}).status_code == 404


def test_out_of_range_rays_are_null_over_http(client):
    ranges = client.get("/topics/scan").json()["ranges"]
    assert len(ranges) == 360
    assert None in ranges
    assert all(r is None or 0.12 <= r <= 3.5 for r in ranges)


@pytest.mark.parametrize(
    ("body", "field"),
    [({"linear_x": "fast", "angular_z": 0.0}, "linear_x"), ({"linear_x": 0.1, "angular_z": math.inf}, "angular_z")],
)
def test_bad_teleop_is_refused_naming_the_field(client, body, field):
    answer = client.post("/mobile/drive", content=json.dumps(body), headers={"content-type": "application/json"})
    assert answer.status_code == 422
    assert field in answer.text


def test_the_page_teleop_drives_the_base(client):
    def turning():
        client.post("/mobile/drive", json={"linear_x": 0.0, "angular_z": 1.0})
        return client.get("/topics/odom").json()["twist"]["twist"]["angular"]["z"] == 1.0

    wait_for(turning, 60)
    assert client.post("/mobile/reset").json() == {"successful": True}
    assert client.get("/topics/ground_truth_pose").json()["x"] == pytest.approx(-1.0, abs=0.01)


def test_a_live_recording_of_the_mobile_world(client, tmp_path):
    lab = client.app.state.lab
    lab.recordings_dir = tmp_path
    started = client.post("/services/start_recording", json={"name": "drive"})
    assert started.status_code == 200, started.text
    start = lab.snapshot().time
    wait_for(
        lambda: (
            client.post("/mobile/drive", json={"linear_x": 0.1, "angular_z": 0.5}) and lab.snapshot().time > start + 1
        )
    )
    stopped = client.post("/services/stop_recording", json={}).json()
    assert stopped["success"]
    assert stopped["messages"] > 10
    download = client.get("/recordings/drive.mcap")
    assert download.status_code == 200
    assert download.content.startswith(b"\x89MCAP0\r\n")
    assert is_mobile(tmp_path / "drive.mcap")
    assert "foxglove.LaserScan" in {m.schema for m in reader.messages(tmp_path / "drive.mcap", ["/scan"])}


def test_a_graded_trials_world_cannot_be_reset(client):
    lab = client.app.state.lab
    lab.graded = True
    try:
        refused = client.post("/mobile/reset")
        assert refused.status_code == 403
        assert "cannot be reset" in refused.text
    finally:
        lab.graded = False


TRIAL_TOKEN = "a-trials-own-token-0123456789"


def test_a_graded_trials_lab_gives_its_program_a_nodes_access_and_nothing_more():
    """A graded trial (app/grading/wall_trial.py): the client without the trial's token (its program) drives
    on /cmd_vel and reads what a robot's node reads; the arena, the ground truth and the monitor are
    not served, and the lab's recording service and the API's driving are refused to it."""
    with TestClient(create_app(MOBILE, MobileLab(MobileConfig(), graded=True), token=TRIAL_TOKEN)) as graded:
        assert graded.get("/mobile/arena").status_code == 403
        names = {t["name"] for t in graded.get("/topics").json()}
        assert "/scan" in names and "/odom" in names
        assert not names & {"/ground_truth_pose", "/wall_following"}
        assert graded.post("/services/start_recording", json={"name": "stolen"}).status_code == 401
        assert graded.post("/mobile/drive", json={"linear_x": 0.1, "angular_z": 0.0}).status_code == 401
        with graded.websocket_connect("/") as ws:
            ws.send_json({"op": "call_service", "service": "/rosapi/topics", "id": "t"})
            topics = ws.receive_json()["values"]["topics"]
            assert "/cmd_vel" in topics and "/ground_truth_pose" not in topics
            ws.send_json({"op": "call_service", "service": "/start_recording", "args": {"name": "x"}, "id": "r"})
            refused = ws.receive_json()
            assert refused["op"] == "status" and "refused to a graded program" in refused["msg"], refused
            ws.send_json({"op": "advertise", "topic": "/cmd_vel", "type": "geometry_msgs/Twist"})

            def turning():
                twist = {"linear": {"x": 0.0, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": 1.0}}
                ws.send_json({"op": "publish", "topic": "/cmd_vel", "msg": twist})
                return graded.get("/topics/odom").json()["twist"]["twist"]["angular"]["z"] == 1.0

            wait_for(turning)
