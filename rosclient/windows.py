"""cv2's windows in a program `hri-lab run` starts: `cv2.imshow(name, image)` shows the image on the
lab's dashboard (a window per name, like rqt_image_view) instead of failing without a display;
`cv2.waitKey(ms)` paints the windows and waits ms from its call (no key ever comes: -1; 0 waits
until the program is stopped). The rest of OpenCV is the real one: the hook only replaces the window
functions once `import cv2` has run.

As in OpenCV, a window paints in the event loop that `waitKey` (or `pollKey`) runs, not in
`imshow`: imshow keeps a copy of the image, and a program that never calls waitKey shows nothing,
unless it called `cv2.startWindowThread()` (then windows paint at once, as with OpenCV's window
thread). So painting (a JPEG, ~1 ms) is part of waitKey's delay, as it is on a desktop, not time
added to a callback. An image goes as sensor_msgs/CompressedImage (JPEG) on WINDOWS + the name made
a ROS name, with the window's name in header.frame_id, at most MAX_RATE_HZ per window (the newest
shown is kept for the next paint).
"""

from __future__ import annotations

import base64
import importlib.abc
import importlib.machinery
import re
import sys
import threading
import time
from typing import Any

from interfaces.image_windows import WINDOWS

MAX_RATE_HZ = 15.0
JPEG_QUALITY = 80
_lock = threading.Lock()
_shown: dict[str, tuple[str, Any]] = {}  # topic -> (window name, image) shown since the window last painted
_last_sent: dict[str, float] = {}
_window_thread = [False]  # cv2.startWindowThread() was called: windows paint as they are shown


def topic_of(name: str) -> str:
    """A window's topic: its name with every character a ROS name cannot have as '_'."""
    return WINDOWS + (re.sub(r"[^A-Za-z0-9_]", "_", str(name)) or "_")


def imshow(cv2: Any, name: str, image: Any) -> None:
    """Keep `image` (a copy in 8 bits, as OpenCV shows it) for window `name`'s next paint."""
    import numpy as np

    image = np.asarray(image)
    if image.size == 0:  # OpenCV refuses it in imshow, not at the paint
        raise cv2.error(f"imshow: the image of window '{name}' is empty (size.width>0 && size.height>0)")
    if image.dtype.kind == "f":  # OpenCV shows floats as 0..1
        image = np.clip(image * 255.0, 0, 255).astype(np.uint8)
    elif image.dtype == np.uint16:
        image = (image >> 8).astype(np.uint8)
    elif image.dtype != np.uint8:
        image = np.clip(image, 0, 255).astype(np.uint8)
    else:
        image = image.copy()  # the program may change its array before the window paints
    with _lock:
        _shown[topic_of(name)] = (str(name), image)
    if _window_thread[0]:
        paint(cv2)


def paint(cv2: Any) -> None:
    """Publish each window's newest image shown, at most MAX_RATE_HZ per window (one shown sooner
    waits for a later paint)."""
    from rosclient import process

    now = time.monotonic()
    with _lock:
        due = [
            (topic, shown) for topic, shown in _shown.items() if now - _last_sent.get(topic, -1e9) >= 1.0 / MAX_RATE_HZ
        ]
        for topic, _ in due:
            del _shown[topic]
            _last_sent[topic] = now
    for topic, (name, image) in due:
        ok, data = cv2.imencode(".jpg", image, [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY])
        if not ok:
            raise cv2.error(f"imshow: the image of window '{name}' could not be encoded")
        wall = time.time()
        message = {
            "header": {"stamp": {"sec": int(wall), "nanosec": int((wall % 1) * 1e9)}, "frame_id": name},
            "format": "jpeg",
            "data": base64.b64encode(data.tobytes()).decode("ascii"),
        }
        process.publish(topic, "sensor_msgs/CompressedImage", message)


def wait_key(cv2: Any, delay: int = 0) -> int:
    """Paint the windows, then wait until `delay` ms from the call; no key ever comes: -1."""
    from rosclient import process

    deadline = time.monotonic() + delay / 1000.0
    paint(cv2)
    if delay <= 0:  # until a key that never comes: until the program is stopped (Ctrl+C)
        process.shutdown_event.wait()
    else:
        process.shutdown_event.wait(max(0.0, deadline - time.monotonic()))
    return -1


def poll_key(cv2: Any) -> int:
    """cv2.pollKey: paint the windows, wait for nothing; no key ever comes: -1."""
    paint(cv2)
    return -1


def start_window_thread() -> int:
    """cv2.startWindowThread: from now on a window paints as it is shown, without waitKey."""
    _window_thread[0] = True
    return 1


def patch(cv2: Any) -> None:
    """Replace cv2's window functions by the dashboard's."""
    cv2.imshow = lambda winname, mat: imshow(cv2, winname, mat)
    cv2.waitKey = lambda delay=0: wait_key(cv2, delay)
    cv2.pollKey = lambda: poll_key(cv2)
    cv2.waitKeyEx = cv2.waitKey
    cv2.startWindowThread = start_window_thread
    for name in ("namedWindow", "destroyWindow", "destroyAllWindows", "resizeWindow", "moveWindow",
                 "setWindowTitle"):  # fmt: skip
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
