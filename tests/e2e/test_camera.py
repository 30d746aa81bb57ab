"""The camera against a real server: /image_raw and /camera_info over HTTP and rosbridge (roslibpy,
base64 data as rosbridge_suite sends it), GET /camera/image.png, and the handout's detection node
(tests/ros_programs/object_detector_rospy.py) run with `hri-lab run`: its get_target_position
answers within 5 px of the lab's own, with the box at rest and while the person carries it; its
cv2.imshow window reaches the dashboard's API."""

import base64
import itertools
import time

import cv2
import numpy as np
import pytest
import roslibpy

from tests.e2e.serving import running_server
from tests.http_client import http
from tests.ros_running import run
from tests.waiting import wait_for

TOLERANCE_PX = 5
DETECTED = "detected_target_position"  # the node's service, remapped beside the lab's own


@pytest.fixture(scope="module")
def lab():
    with running_server("--view", "none") as server:
        yield server


def lab_pixel(lab) -> np.ndarray:
    answer = http.post(f"{lab.url}/services/get_target_position", json={"get": True}, timeout=30).json()
    return np.array([answer["x"], answer["y"]])


def distance_to_path(point: np.ndarray, path: list[np.ndarray]) -> float:
    """px from a point to the polyline through the path's pixels (one pixel: to that pixel)."""
    point = point.astype(float)
    best = float(np.linalg.norm(point - path[0]))
    for a, b in itertools.pairwise(path):
        a, b = a.astype(float), b.astype(float)
        span = b - a
        share = np.clip((point - a) @ span / max(span @ span, 1e-9), 0.0, 1.0)
        best = min(best, float(np.linalg.norm(point - (a + share * span))))
    return best


def test_the_image_over_http_is_the_cameras_png_and_the_info_its_intrinsics(lab):
    response = http.get(f"{lab.url}/camera/image.png", timeout=60)
    assert response.status_code == 200
    assert response.headers["content-type"] == "image/png"
    image = cv2.imdecode(np.frombuffer(response.content, np.uint8), cv2.IMREAD_COLOR)
    assert image.shape == (480, 640, 3)
    message = http.get(f"{lab.url}/topics/image_raw", timeout=60).json()
    assert (message["encoding"], message["height"], message["width"], message["step"]) == ("bgr8", 480, 640, 1920)
    assert message["header"]["frame_id"] == "camera_optical"
    assert len(base64.b64decode(message["data"])) == 480 * 1920
    info = http.get(f"{lab.url}/topics/camera_info", timeout=30).json()
    assert info["k"] == [500.0, 0.0, 320.0, 0.0, 500.0, 240.0, 0.0, 0.0, 1.0]
    assert info["p"][:3] == [500.0, 0.0, 320.0]
    assert info["d"] == [0.0] * 5
    refused = http.get(f"{lab.url}/camera/image.gif", timeout=30)
    assert refused.status_code == 422
    assert "kind" in refused.text


def test_image_raw_streams_over_the_http_websocket(lab):
    import json

    from websockets.sync.client import connect

    with connect(f"ws://127.0.0.1:{lab.port}/topics/image_raw/stream?rate=5", max_size=None, open_timeout=30) as ws:
        first, second = json.loads(ws.recv(timeout=60)), json.loads(ws.recv(timeout=60))
    stamps = [m["header"]["stamp"]["sec"] + m["header"]["stamp"]["nanosec"] * 1e-9 for m in (first, second)]
    assert first["encoding"] == "bgr8"
    assert len(base64.b64decode(second["data"])) == 480 * 640 * 3
    assert stamps[1] - stamps[0] >= 0.2 - 0.0005  # at most 5 a second of simulated time


def test_image_raw_over_rosbridge_is_base64_bgr8_stamped_with_sim_time(lab):
    client = roslibpy.Ros("127.0.0.1", lab.port, transport="asyncio")  # the transport the other tests use
    client.run()
    got = []
    topic = roslibpy.Topic(client, "/image_raw", "sensor_msgs/Image", throttle_rate=100)
    topic.subscribe(got.append)
    try:
        wait_for(lambda: len(got) >= 2, timeout=60)
    finally:
        topic.unsubscribe()
        client.close()
        client.terminate()
    first, second = got[0], got[1]
    image = np.frombuffer(base64.b64decode(first["data"]), np.uint8).reshape(480, 640, 3)
    assert image.std() > 0  # a scene, not a blank
    stamp = lambda m: m["header"]["stamp"]["sec"] + m["header"]["stamp"]["nanosec"] * 1e-9  # noqa: E731 - a one-line helper read twice just below
    assert stamp(second) >= stamp(first) + 0.1 - 0.0005  # throttle_rate 100 ms of simulated time
    wait_for(lambda: not http.get(f"{lab.url}/health", timeout=30).is_error)


def test_the_detection_node_answers_within_5_px_at_rest_and_while_carried(lab):
    program = run(lab.url, "object_detector_rospy.py", f"get_target_position:={DETECTED}")
    try:
        program.wait_for_line("detector ready")

        def detected():
            answer = http.post(f"{lab.url}/services/{DETECTED}", json={"get": True}, timeout=30)
            return np.array([answer.json()["x"], answer.json()["y"]]) if answer.status_code == 200 else None

        def first_detection():
            pixel = detected()
            return tuple(pixel) if pixel is not None and pixel.any() else None

        at_rest = np.array(wait_for(first_detection, timeout=90))  # its first images came
        assert np.abs(detected() - lab_pixel(lab)).max() <= TOLERANCE_PX, at_rest
        # the person lifts and carries the box: each answer is within 5 px of the path the box took in
        # the image since the lift began (the lab's answers, a polyline): the node answers from the
        # last image it got, which on a loaded machine may be seconds old, so no lag is bounded here
        # (a bound on the machine's speed); and its answers follow the box away from where it rested
        start = lab_pixel(lab)
        assert http.post(f"{lab.url}/services/start_cooperative_lifting", json={"force": 10.0}).status_code == 200
        path = [start]
        checked, followed = 0, False
        end = time.monotonic() + 120
        while time.monotonic() < end and (checked < 30 or not followed):
            answer = detected()
            path.append(lab_pixel(lab))
            if answer is not None and np.abs(path[-1] - start).max() > 10:  # the box moved in the image
                assert distance_to_path(answer, path) <= TOLERANCE_PX, (answer, path[-5:])
                followed = followed or np.abs(answer - start).max() > 10
                checked += 1
        assert checked >= 10 and followed, "the box was not carried across the image, or the node never saw it move"
        windows = wait_for(lambda: http.get(f"{lab.url}/camera/windows", timeout=30).json())
        assert windows[0]["name"] == "detection"
        assert windows[0]["topic"] == "/image_windows/detection"
        shown = http.get(f"{lab.url}/camera/windows/detection.jpg", timeout=30)
        assert shown.headers["content-type"] == "image/jpeg"
        assert cv2.imdecode(np.frombuffer(shown.content, np.uint8), cv2.IMREAD_COLOR).shape == (480, 640, 3)
    finally:
        assert program.interrupt() == 0, program.output
    wait_for(lambda: http.get(f"{lab.url}/camera/windows", timeout=30).json() == [])  # gone with its program


def test_an_rclpy_detection_node_answers_as_the_lab_does(lab):
    program = run(lab.url, "object_detector_rclpy.py", "--ros-args", "-r", f"get_target_position:={DETECTED}_rclpy")
    try:
        program.wait_for_line("detector ready")

        def detected():
            answer = http.post(f"{lab.url}/services/{DETECTED}_rclpy", json={"get": True}, timeout=30)
            pixel = (answer.json()["x"], answer.json()["y"]) if answer.status_code == 200 else (0, 0)
            return pixel if any(pixel) else None

        wait_for(detected, timeout=90)  # its first images came
        http.post(f"{lab.url}/services/reset_simulation", timeout=30)
        wait_for(lambda: np.abs(np.array(detected()) - lab_pixel(lab)).max() <= TOLERANCE_PX, timeout=60)
    finally:
        assert program.interrupt() == 0, program.output
