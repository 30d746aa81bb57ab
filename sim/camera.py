"""The lab's fixed virtual camera at the person's side, looking at the workspace: a pinhole camera of
640 x 480 px, no distortion. The one source of its intrinsics and extrinsics: `/get_target_position`
projects with it, the rendered image (sim/camera_render.py) is drawn through it and
`/camera_info` publishes it (sim/messages.py).

Frames: `base` (panda_link0, z up) and the camera's optical frame `camera_optical` (ROS's
convention: x right, y down, z forward along the viewing direction), at CAMERA_POSITION.
"""

from __future__ import annotations

import numpy as np

CAMERA_POSITION = np.array([0.45, 1.60, 0.60])  # m, base frame
CAMERA_TARGET = np.array([0.45, 0.20, 0.40])  # m, base frame (on the optical axis)
CAMERA_FOCAL = 500.0  # px (fx = fy)
CAMERA_SIZE = (640, 480)  # px (width, height)
OPTICAL_FRAME = "camera_optical"


def rotation_optical_to_base() -> np.ndarray:
    """3x3 whose columns are the optical frame's axes in the base frame: x right = z x up,
    y down = z x right, z = the viewing direction (CAMERA_TARGET - CAMERA_POSITION)."""
    forward = CAMERA_TARGET - CAMERA_POSITION
    forward = forward / np.linalg.norm(forward)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    down = np.cross(forward, right)
    return np.column_stack((right, down, forward))


def transform_optical_to_base() -> np.ndarray:
    """4x4 pose of the optical frame in the base frame (m)."""
    transform = np.eye(4)
    transform[:3, :3] = rotation_optical_to_base()
    transform[:3, 3] = CAMERA_POSITION
    return transform


def intrinsics() -> np.ndarray:
    """K (3x3, px): fx = fy = CAMERA_FOCAL, principal point at the image centre (w/2, h/2)."""
    width, height = CAMERA_SIZE
    return np.array([[CAMERA_FOCAL, 0.0, width / 2], [0.0, CAMERA_FOCAL, height / 2], [0.0, 0.0, 1.0]])


def project_exact(point_base: np.ndarray) -> tuple[float, float]:
    """Pixel coordinates (x right, y down, px, not rounded) of a base-frame point (m):
    (u, v, 1) ~ K R^T (point - CAMERA_POSITION). Raises ValueError behind the camera."""
    rel = rotation_optical_to_base().T @ (np.asarray(point_base, float) - CAMERA_POSITION)
    if rel[2] <= 1e-6:
        raise ValueError("the point is behind the camera")
    u, v, _ = intrinsics() @ (rel / rel[2])
    return float(u), float(v)


def project(point_base: np.ndarray) -> tuple[int, int]:
    """The pixel (x right, y down) of a base-frame point (m), rounded; ValueError behind the camera."""
    u, v = project_exact(point_base)
    return int(round(u)), int(round(v))


def box_in_image(position_base: np.ndarray, rotation_box_to_base: np.ndarray, size: np.ndarray) -> tuple[int, int]:
    """The box's centre in the image as a detector finds it (px, rounded): the centre of the bounding
    rectangle of its 8 projected corners, which is what `cv2.boundingRect` of its silhouette gives
    (the projection of the box's centre lies a few px off it: perspective). ValueError when a corner
    is behind the camera."""
    signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    corners = (
        np.asarray(position_base, float)
        + (signs * np.asarray(size, float) / 2) @ np.asarray(rotation_box_to_base, float).T
    )
    pixels = np.array([project_exact(c) for c in corners])
    low, high = pixels.min(axis=0), pixels.max(axis=0)
    return int(round((low[0] + high[0]) / 2)), int(round((low[1] + high[1]) / 2))
