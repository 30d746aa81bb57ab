"""`hri-lab urdf view`: the 3D view of a student's URDF serves, with a slider per movable joint
whose moves reach `/joint_states` over rosbridge (roslibpy, unchanged) and HTTP, and the
`/robot_description` parameter is the file's text (app/view/urdf_view.py, app/view/urdf_bridge.py)."""

import math
import subprocess
import sys
import threading
from pathlib import Path

import httpx
import numpy as np
import pytest
import roslibpy
import uvicorn

from sim.robot.urdf_check import parse_urdf_file

from app.serving.launch import free_port
from app.view.urdf_bridge import urdf_app
from app.view.urdf_view import UrdfView
from tests.http_client import http
from tests.waiting import process_gone, wait_for

PAN_TILT = Path(__file__).resolve().parents[2] / "examples/urdf/pan_tilt.urdf"


@pytest.fixture(scope="module")
def view():
    """The view in this process, its bridge served by uvicorn in a thread (stopped at the end)."""
    shown = UrdfView(PAN_TILT, parse_urdf_file(PAN_TILT), port=free_port())
    port = free_port()
    server = uvicorn.Server(
        uvicorn.Config(
            urdf_app(shown.states, PAN_TILT.read_text(), shown.url), host="127.0.0.1", port=port, log_level="warning"
        )
    )
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    wait_for(lambda: server.started)
    shown.bridge_port = port
    yield shown
    server.should_exit = True
    thread.join(30)
    shown.stop()


@pytest.fixture(scope="module")
def ros(view):
    client = roslibpy.Ros("127.0.0.1", view.bridge_port, transport="asyncio")
    client.run(timeout=30)
    yield client
    client.close()
    client.terminate()


def test_a_slider_per_movable_joint_with_the_files_limits(view):
    assert list(view.sliders) == ["pan_joint", "tilt_joint"]
    tilt = view.sliders["tilt_joint"]
    assert (tilt.min, tilt.max, tilt.value) == (-0.79, 0.79, 0.0)
    assert (view.sliders["pan_joint"].min, view.sliders["pan_joint"].max) == (-3.14, 3.14)
    assert http.get(view.url, timeout=30).status_code == 200  # viser's page


def test_moving_a_slider_reaches_joint_states(view, ros):
    received = []
    topic = roslibpy.Topic(ros, "/joint_states", "sensor_msgs/JointState")
    topic.subscribe(received.append)
    try:
        wait_for(lambda: received)
        assert received[-1]["name"] == ["pan_joint", "tilt_joint"]
        view.sliders["tilt_joint"].value = 0.5  # as a drag in the page does: the slider's update callbacks
        latest = wait_for(lambda: received[-1]["position"] if received[-1]["position"][1] == 0.5 else None)
        assert latest == [0.0, 0.5]
        over_http = http.get(f"http://127.0.0.1:{view.bridge_port}/topics/joint_states").json()
        assert over_http["position"] == [0.0, 0.5]
    finally:
        topic.unsubscribe()
        view.centre()
    assert view.states.positions() == [0.0, 0.0]


def test_a_value_outside_the_range_is_kept_in_it(view):
    tilt = view.sliders["tilt_joint"]
    try:
        tilt.value = 5.0  # what a forged page message could send
        assert (tilt.value, view.states.position("tilt_joint")) == (0.79, 0.79)
        tilt.value = float("nan")
        assert (tilt.value, view.states.position("tilt_joint")) == (0.79, 0.79)
    finally:
        view.centre()


def test_frames_on_request_sit_where_the_file_puts_them(view):
    tilt_frame = view._frames["tilt_link"]
    assert not tilt_frame.visible
    view.sliders["pan_joint"].value = 0.5
    view.show_frames.value = True
    try:
        assert tilt_frame.visible
        # tilt_link: 0.025 m (pan_joint's origin) + 0.16 m (tilt_joint's) above the base, turned 0.5 rad about z
        np.testing.assert_allclose(tilt_frame.position, [0.0, 0.0, 0.185], atol=1e-9)
        np.testing.assert_allclose(np.abs(tilt_frame.wxyz), [math.cos(0.25), 0.0, 0.0, math.sin(0.25)], atol=1e-9)
    finally:
        view.show_frames.value = False
        view.centre()


def test_robot_description_is_the_files_text(view, ros):
    assert roslibpy.Param(ros, "/robot_description").get(timeout=30) == PAN_TILT.read_text()
    assert ros.get_topics() == ["/joint_states"]
    assert http.get(f"http://127.0.0.1:{view.bridge_port}/robot_description").text == PAN_TILT.read_text()


def cli(*args: str, **kwargs):
    return subprocess.Popen([sys.executable, "-m", "app.cli", "urdf", *args], text=True, **kwargs)


def test_the_command_serves_and_stops():
    port = free_port()
    view = cli("view", str(PAN_TILT), "--port", str(port), stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    try:
        lines = []
        for line in view.stdout:  # ends when the process does
            lines.append(line)
            if "Ctrl+C" in line:
                break
        assert any("2 movable joint(s)" in line for line in lines), "".join(lines)
        view_url = next(line.split()[-1] for line in lines if line.strip().startswith("3D view"))
        wait_for(lambda: _answers(f"http://127.0.0.1:{port}/"))
        assert http.get(view_url, timeout=30).status_code == 200
        echo = subprocess.run(
            [
                sys.executable,
                "-m",
                "app.cli",
                "topic",
                "echo",
                "/joint_states",
                "--once",
                "--url",
                f"http://127.0.0.1:{port}",
            ],
            capture_output=True,
            text=True,
            timeout=60,
        )
        assert echo.returncode == 0 and "pan_joint" in echo.stdout, echo.stderr
        ros = roslibpy.Ros("127.0.0.1", port, transport="asyncio")
        ros.run(timeout=30)
        try:
            assert roslibpy.Param(ros, "/robot_description").get(timeout=30) == PAN_TILT.read_text()
        finally:
            ros.close()
            ros.terminate()
    finally:
        view.terminate()
        view.wait(30)
        view.stdout.close()
    assert process_gone(view.pid)


def _answers(url: str) -> bool:
    try:
        return http.get(url, timeout=5).status_code == 200
    except httpx.HTTPError:
        return False


def test_a_broken_file_is_the_checks_error_and_exit_1():
    broken = Path(__file__).resolve().parents[1] / "data/urdf/bad_parent.urdf"
    view = cli("view", str(broken), stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    out, err = view.communicate(timeout=120)
    assert view.returncode == 1
    assert out == ""
    assert err.strip() == (
        f"error: {broken}:36: joint 'tilt_joint': its parent link 'pan_lnk' does not exist: "
        "expected one of base_link, pan_link, tilt_link"
    )
