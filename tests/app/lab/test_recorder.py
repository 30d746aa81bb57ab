"""Recording the live lab: the service pair, its refusals, the download, and a file finished on
the server's shutdown."""

import io
import itertools
import time

import pytest
from fastapi.testclient import TestClient
from mcap.reader import make_reader

from sim.recording import reader

from app.lab.lab import Lab
from app.lab.world import LIFTING
from app.serving.compose import create_app


def wait_sim(client, seconds: float) -> None:
    """Until the simulation advanced `seconds` (however loaded the machine is)."""
    start = client.get("/health").json()["sim_time"]
    deadline = time.monotonic() + 60
    while client.get("/health").json()["sim_time"] < start + seconds and time.monotonic() < deadline:
        time.sleep(0.05)


def test_start_and_stop_recording_the_live_lab(client, lab, tmp_path):
    lab.recordings_dir = tmp_path
    started = client.post("/services/start_recording", json={"name": "live"})
    assert started.status_code == 200
    assert started.json()["path"] == str(tmp_path / "live.mcap")
    again = client.post("/services/start_recording", json={"name": "other"})
    assert again.status_code == 400
    assert "already recording" in again.json()["detail"]
    assert client.post("/services/start_cooperative_lifting", json={"force": 10}).status_code == 200
    wait_sim(client, 0.5)
    assert client.get("/recordings").json() == [
        {"name": "live.mcap", "bytes": pytest.approx(0, abs=10**7), "recording": True}
    ]
    stopped = client.post("/services/stop_recording", json={}).json()
    assert stopped["success"]
    assert stopped["messages"] > 0
    download = client.get("/recordings/live.mcap")
    assert download.status_code == 200
    assert len(download.content) == stopped["bytes"]
    summary = make_reader(io.BytesIO(download.content)).get_summary()  # finished: indexed, with a summary
    counts = {summary.channels[c].topic: n for c, n in summary.statistics.channel_message_counts.items()}
    assert counts["/tf"] == 11 * counts["/scene"]
    assert counts["/joint_states"] > 1
    stamps = [
        m.data["header"]["stamp"]["sec"] + m.data["header"]["stamp"]["nanosec"] * 1e-9
        for m in reader.messages(tmp_path / "live.mcap", ["/joint_states"])
    ]
    steps = [b - a for a, b in itertools.pairwise(stamps)]
    assert min(steps) >= 0.01 - 1e-6  # decimated to 100 Hz of simulated time
    assert stamps[-1] - stamps[0] >= 0.4  # over the 0.5 s recorded (a loaded machine may skip samples, not the span)
    assert any(m.data["started"] for m in reader.messages(tmp_path / "live.mcap", ["/lifting_state"]))
    not_recording = client.post("/services/stop_recording", json={})
    assert not_recording.status_code == 400
    assert "not recording" in not_recording.json()["detail"]


@pytest.mark.parametrize(
    ("body", "field"),
    [
        ({"name": "../escape"}, "name"),
        ({"name": ".hidden"}, "name"),
        ({"max_mb": 0}, "max_mb"),
        ({"max_mb": "NaN"}, "max_mb"),
    ],
)
def test_bad_recording_requests_name_the_field(client, body, field):
    response = client.post("/services/start_recording", json=body)
    assert response.status_code == 422
    assert response.json()["detail"][0]["loc"][-1] == field


def test_file_routes_refuse_paths_out_of_their_folder(client):
    assert client.get("/recordings/..%2Fpyproject.toml").status_code == 404
    assert client.get("/figures/x/..").status_code == 404
    assert client.get("/recordings/missing.mcap").status_code == 404


def test_a_recording_is_finished_on_shutdown(tmp_path):
    lab = Lab()
    lab.recordings_dir = tmp_path
    with TestClient(create_app(LIFTING, lab)) as client:
        assert client.post("/services/start_recording", json={"name": "shutdown"}).status_code == 200
        wait_sim(client, 0.2)
    bag = reader.info(tmp_path / "shutdown.mcap")  # the server stopped without /stop_recording
    assert bag.complete
    assert bag.messages > 0


def test_a_live_recording_has_the_cameras_images_in_foxgloves_schema(client, lab, tmp_path):
    import base64

    import cv2
    import numpy as np

    from sim.recording.writer import IMAGE_TOPIC

    from tests.waiting import wait_for

    lab.recordings_dir = tmp_path
    assert client.post("/services/start_recording", json={"name": "camera"}).status_code == 200
    first = lab.camera.number
    wait_for(lambda: lab.camera.number >= first + 3, timeout=120)  # the recording wants images
    stopped = client.post("/services/stop_recording", json={}).json()
    assert stopped["success"]
    with open(tmp_path / "camera.mcap", "rb") as handle:
        summary = make_reader(handle).get_summary()
    channel = next(c for c in summary.channels.values() if c.topic == IMAGE_TOPIC)
    assert summary.schemas[channel.schema_id].name == "foxglove.CompressedImage"
    images = list(reader.messages(tmp_path / "camera.mcap", [IMAGE_TOPIC]))
    assert images
    assert images[0].data["format"] == "jpeg"
    assert images[0].data["frame_id"] == "camera_optical"
    picture = cv2.imdecode(np.frombuffer(base64.b64decode(images[0].data["data"]), np.uint8), cv2.IMREAD_COLOR)
    assert picture.shape == (480, 640, 3)
