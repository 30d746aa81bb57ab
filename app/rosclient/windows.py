"""cv2's windows in a program `hri-lab run` starts: `cv2.imshow(name, image)` publishes the image to
the lab's dashboard (a window per name, like rqt_image_view) instead of failing without a display;
`cv2.waitKey(ms)` waits ms (no key ever comes: -1; 0 waits until the program is stopped). The rest
of OpenCV is the real one: the hook only replaces the window functions once `import cv2` has run.

An image goes as sensor_msgs/CompressedImage (JPEG) on WINDOWS + the name made a ROS name, with
the window's name in header.frame_id, at most MAX_RATE_HZ per window (the newest is kept).
"""

from __future__ import annotations

import base64
import importlib.abc
import importlib.machinery
import re
import sys
import time
from typing import Any

from app.interfaces.image_windows import WINDOWS

MAX_RATE_HZ = 15.0
JPEG_QUALITY = 80
_last_sent: dict[str, float] = {}


def topic_of(name: str) -> str:
    """A window's topic: its name with every character a ROS name cannot have as '_'."""
    return WINDOWS + (re.sub(r"[^A-Za-z0-9_]", "_", str(name)) or "_")


def imshow(cv2: Any, name: str, image: Any) -> None:
    import numpy as np

    from app.rosclient import process

    topic = topic_of(name)
    now = time.monotonic()
    if now - _last_sent.get(topic, -1e9) < 1.0 / MAX_RATE_HZ:
        return
    _last_sent[topic] = now
    image = np.asarray(image)
    if image.dtype.kind == "f":  # OpenCV shows floats as 0..1
        image = np.clip(image * 255.0, 0, 255).astype(np.uint8)
    elif image.dtype == np.uint16:
        image = (image >> 8).astype(np.uint8)
    elif image.dtype != np.uint8:
        image = np.clip(image, 0, 255).astype(np.uint8)
    ok, data = cv2.imencode(".jpg", image, [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY])
    if not ok:
        raise cv2.error(f"imshow: the image of window '{name}' could not be encoded")
    wall = time.time()
    message = {
        "header": {"stamp": {"sec": int(wall), "nanosec": int((wall % 1) * 1e9)}, "frame_id": str(name)},
        "format": "jpeg",
        "data": base64.b64encode(data.tobytes()).decode("ascii"),
    }
    process.publish(topic, "sensor_msgs/CompressedImage", message)


def wait_key(delay: int = 0) -> int:
    from app.rosclient import process

    if delay <= 0:  # until a key that never comes: until the program is stopped (Ctrl+C)
        process.shutdown_event.wait()
    else:
        process.shutdown_event.wait(delay / 1000.0)
    return -1


def patch(cv2: Any) -> None:
    """Replace cv2's window functions by the dashboard's."""
    cv2.imshow = lambda winname, mat: imshow(cv2, winname, mat)
    cv2.waitKey = lambda delay=0: wait_key(delay)
    cv2.pollKey = lambda: -1
    cv2.waitKeyEx = cv2.waitKey
    for name in ("namedWindow", "destroyWindow", "destroyAllWindows", "startWindowThread", "resizeWindow",
                 "moveWindow", "setWindowTitle"):  # fmt: skip
        setattr(cv2, name, lambda *args, **kwargs: None)


class _Loader(importlib.abc.Loader):
    def __init__(self, real: Any, hook: Hook) -> None:
        self.real, self.hook = real, hook

    def create_module(self, spec):
        return self.real.create_module(spec)

    def exec_module(self, module) -> None:
        self.hook.busy = True  # cv2's own bootstrap imports cv2 again: that one is OpenCV's
        try:
            self.real.exec_module(module)
        finally:
            self.hook.busy = False
        patch(sys.modules.get("cv2", module))


class Hook(importlib.abc.MetaPathFinder):
    """Finds the real cv2 and patches it once it is imported."""

    busy = False

    def find_spec(self, fullname, path, target=None):
        if fullname != "cv2" or self.busy:
            return None
        spec = importlib.machinery.PathFinder.find_spec(fullname, path)
        if spec is None or spec.loader is None:
            return None
        spec.loader = _Loader(spec.loader, self)
        return spec


def install() -> None:
    if not any(isinstance(finder, Hook) for finder in sys.meta_path):
        sys.meta_path.insert(0, Hook())
