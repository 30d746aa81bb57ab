"""The lab's fixed virtual camera at the person's side, looking at the workspace (pinhole, 640 x 480)."""

from __future__ import annotations

import numpy as np

CAMERA_POSITION = np.array([0.45, 1.60, 0.60])  # m, base frame
CAMERA_TARGET = np.array([0.45, 0.20, 0.40])  # m, base frame
CAMERA_FOCAL = 500.0  # px
CAMERA_SIZE = (640, 480)  # px


def project(point_base: np.ndarray) -> tuple[int, int]:
    """Pixel (x right, y down) of a base-frame point (m):
    u = w/2 + f (r . p) / (z . p),  v = h/2 + f (d . p) / (z . p),  p = point - camera,
    z = viewing direction, r = z x up, d = z x r. Raises ValueError behind the camera."""
    forward = CAMERA_TARGET - CAMERA_POSITION
    forward = forward / np.linalg.norm(forward)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    rel = np.asarray(point_base, float) - CAMERA_POSITION
    depth = rel @ forward
    if depth <= 1e-6:
        raise ValueError("the point is behind the camera")
    u = CAMERA_SIZE[0] / 2 + CAMERA_FOCAL * (rel @ right) / depth
    v = CAMERA_SIZE[1] / 2 + CAMERA_FOCAL * (rel @ down) / depth
    return int(round(u)), int(round(v))
