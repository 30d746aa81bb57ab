"""tf2's messages of any world: a child frame's pose in its parent's frame as a
geometry_msgs/TransformStamped, and the root frame every world's tree hangs from (a world's own
frames: its package, e.g. app/lab/tf.py; the programs' frames: app/rosbridge/internal/node_frames.py)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import pinocchio as pin

from sim.messages import header

WORLD = "world"  # the root frame (tf2_web_republisher's default target frame)


def relative_stamped(
    s: Any, parent: str, child: str, relative: np.ndarray, rotation_xyzw: Sequence[float] | np.ndarray | None = None
) -> dict:
    """geometry_msgs/TransformStamped of `relative`, the child's pose (4x4) in the parent's frame,
    stamped with the snapshot `s`'s simulated time; its rotation `rotation_xyzw` where the caller
    composed it (tf2's sign), else read from the matrix."""
    x, y, z, w = pin.Quaternion(relative[:3, :3]).coeffs() if rotation_xyzw is None else rotation_xyzw
    t = relative[:3, 3]
    return {
        "header": header(s, parent),
        "child_frame_id": child,
        "transform": {
            "translation": {"x": float(t[0]), "y": float(t[1]), "z": float(t[2])},
            "rotation": {"x": float(x), "y": float(y), "z": float(z), "w": float(w)},
        },
    }
