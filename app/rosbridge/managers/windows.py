"""The windows programs open with cv2.imshow: each window's topic (under interfaces.image_windows'
WINDOWS) and its newest image, which the dashboard shows (app/api/camera.py). A window goes when
the last publisher of its topic does (managers/topics.py)."""

from __future__ import annotations


class Windows:
    def __init__(self) -> None:
        self._images: dict[str, dict] = {}  # a window's topic -> its newest image (sensor_msgs/Image as JSON)

    def show(self, topic: str, image: dict) -> None:
        self._images[topic] = image

    def close(self, topic: str) -> None:
        """The program that showed `topic` is gone (nothing when no window is open on it)."""
        self._images.pop(topic, None)

    def get(self, topic: str) -> dict | None:
        return self._images.get(topic)

    def shown(self) -> dict[str, dict]:
        """Every open window's topic -> its newest image (a copy: the event loop may change them)."""
        return dict(self._images)
