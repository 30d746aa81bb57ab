"""cv2's windows in a program (rosclient/windows.py): as in OpenCV, `imshow` keeps the image and
the window paints in `waitKey` / `pollKey` (or at once after `startWindowThread`); the dashboard
gets each window's newest image as JPEG, at most MAX_RATE_HZ a window."""

import base64
import time

import cv2
import numpy as np
import pytest

from rosclient import process, windows


@pytest.fixture
def painted(monkeypatch):
    """The images the windows published, decoded: (topic, window name, BGR image)."""
    sent = []

    def publish(topic, type_name, msg):
        assert type_name == "sensor_msgs/CompressedImage" and msg["format"] == "jpeg"
        data = np.frombuffer(base64.b64decode(msg["data"]), np.uint8)
        sent.append((topic, msg["header"]["frame_id"], cv2.imdecode(data, cv2.IMREAD_COLOR)))

    monkeypatch.setattr(process, "publish", publish)
    monkeypatch.setattr(windows, "_shown", {})
    monkeypatch.setattr(windows, "_last_sent", {})
    monkeypatch.setattr(windows, "_window_thread", [False])
    return sent


def image(value):
    return np.full((48, 64, 3), value, np.uint8)


def test_a_window_paints_in_waitkey_not_in_imshow(painted):
    windows.imshow(cv2, "detection", image(200))
    assert painted == []  # OpenCV: without waitKey the window shows nothing
    assert windows.wait_key(cv2, 1) == -1  # no key ever comes
    [(topic, name, shown)] = painted
    assert (topic, name) == ("/image_windows/detection", "detection")
    assert abs(int(shown.mean()) - 200) <= 2  # JPEG


def test_painting_is_part_of_waitkeys_delay(painted):
    windows.imshow(cv2, "camera", np.zeros((480, 640, 3), np.uint8))
    start = time.monotonic()
    windows.wait_key(cv2, 50)
    assert len(painted) == 1
    assert time.monotonic() - start >= 0.050  # the delay is from the call, painting included


def test_imshow_keeps_a_copy_the_program_may_change_its_array_after(painted):
    frame = image(40)
    windows.imshow(cv2, "w", frame)
    frame[:] = 250
    windows.poll_key(cv2)
    assert abs(int(painted[0][2].mean()) - 40) <= 2


def test_a_window_paints_at_most_max_rate_hz_the_newest_image_kept(painted):
    windows.imshow(cv2, "w", image(10))
    windows.poll_key(cv2)
    windows.imshow(cv2, "w", image(100))
    windows.imshow(cv2, "w", image(180))
    windows.poll_key(cv2)  # within 1/MAX_RATE_HZ of the last paint: kept for later
    assert len(painted) == 1
    last = windows._last_sent["/image_windows/w"]
    windows._last_sent["/image_windows/w"] = last - 1.0 / windows.MAX_RATE_HZ  # as if that long ago
    windows.poll_key(cv2)
    assert len(painted) == 2 and abs(int(painted[1][2].mean()) - 180) <= 2


def test_after_startwindowthread_a_window_paints_as_it_is_shown(painted):
    assert windows.start_window_thread() == 1
    windows.imshow(cv2, "live", image(90).astype(np.float32) / 255.0)  # floats shown as 0..1
    assert len(painted) == 1 and abs(int(painted[0][2].mean()) - 90) <= 2


def test_an_empty_image_is_refused_by_imshow_as_opencv_does(painted):
    with pytest.raises(cv2.error, match="is empty"):
        windows.imshow(cv2, "w", np.zeros((0, 0, 3), np.uint8))
    windows.poll_key(cv2)
    assert painted == []
