"""`hri-lab play`: a recorded trial in the replay view (slider in a real browser) and its topics
over the replay's API."""

import os
import time

import numpy as np
import pytest
import viser
from fastapi.testclient import TestClient
from websockets.exceptions import InvalidStatus
from websockets.sync.client import connect

from sim.controllers.interface import LiftingParams
from sim.procedures.experiment import plan
from sim.procedures.trial import Setup, run_trial
from sim.recording.playback import Playback
from sim.recording.trial import TrialOutputs

from app.serving.launch import free_port
from app.view.replay import ReplayView, replay_app
from bench.page_responsiveness import ARGS, CHROMIUM


@pytest.fixture(scope="module")
def view(tmp_path_factory):
    folder = tmp_path_factory.mktemp("replay")
    result = run_trial(
        *plan(1, "hasty", 0)[0],
        outputs=TrialOutputs(record_dir=str(folder)),
        setup=Setup(params=LiftingParams(alpha=0.8)),
    )  # ~3 s: lifted, dropped at the wider margin
    view = ReplayView(Playback(result.files["recording"]), port=free_port(), light=True)
    view.start()
    yield view
    view.stop()


def placements(view) -> np.ndarray:
    return np.array([frame.position for _, frame in view.robot.frames])


def test_replay_api_serves_the_recorded_topics_at_the_playback_time(view):
    playback = view.playback
    with TestClient(replay_app(view)) as client:
        names = {t["name"]: t["type"] for t in client.get("/topics").json()}
        assert names["/franka_state_controller/F_ext"] == "geometry_msgs/WrenchStamped"
        assert "/tf" not in names
        assert "/scene" not in names
        view.seek(2.0)
        pose = client.get("/topics/object_pose").json()
        stamp = pose["header"]["stamp"]["sec"] + pose["header"]["stamp"]["nanosec"] * 1e-9
        assert 1.99 - 0.01 < stamp - playback.start / 1e9 <= 2.0 + 1e-9  # the last 10 ms sample at or before t
        assert client.get("/replay").json()["time"] == pytest.approx(2.0)
        assert client.get("/topics/nope").status_code == 404


def test_the_slider_moves_the_robot_in_the_browser(view):
    from playwright.sync_api import sync_playwright

    assert os.path.exists(CHROMIUM), "make test installs Debian's chromium-headless-shell"
    view.seek(0.0)
    at_start = placements(view)
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        page = browser.new_page(viewport={"width": 900, "height": 600})
        page.set_default_timeout(60_000)
        page.goto(view.url)
        thumb = page.locator("[role=slider]").first
        thumb.wait_for()
        thumb.focus()
        page.keyboard.press("End")  # scrub to the end, as a person drags the slider there
        page.wait_for_function(
            f"document.querySelector('[role=slider]').getAttribute('aria-valuenow') === '{view.slider.max:g}'"
        )
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline and view.time < view.slider.max:
            time.sleep(0.1)
        browser.close()
    frame = view.playback.frame_at(view.time)
    assert view.time == pytest.approx(view.playback.duration)
    moved = placements(view)
    assert np.max(np.linalg.norm(moved - at_start, axis=1)) > 0.02  # the robot followed the box up
    view.robot.place(frame.q)  # where the recorded q puts the meshes
    np.testing.assert_allclose(moved, placements(view), atol=1e-6)
    np.testing.assert_allclose(view.shapes.box.position, frame.poses["box"][0], atol=1e-6)


def test_play_advances_and_stops_at_the_end(view):
    view.seek(view.playback.duration - 0.2)
    view.speed = 4.0
    view.play()
    deadline = time.monotonic() + 10
    while view.playing and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not view.playing
    assert view.time == view.playback.duration


def test_the_replay_view_refuses_a_foreign_origin(view):
    """Started like the live view (app/view/scene.py guarded_websocket_server): another site's
    page cannot open its WebSocket (and drive the playback)."""
    with pytest.raises(InvalidStatus) as refused:
        connect(
            view.url.replace("http", "ws"), origin="http://evil.example", subprotocols=[f"viser-v{viser.__version__}"]
        )
    assert refused.value.response.status_code == 403
