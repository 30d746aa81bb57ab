"""cv_bridge: sensor_msgs/Image <-> numpy arrays (what OpenCV calls images), without OpenCV.

Encodings: bgr8, rgb8, bgra8, rgba8, mono8, mono16, 8UC1/3/4, 16UC1, 32FC1, 64FC1; between the
colour ones and mono8 as cv_bridge converts (channel order; grey = 0.299 R + 0.587 G + 0.114 B,
OpenCV's weights). 'passthrough' keeps the message's encoding.
"""
from __future__ import annotations

from typing import Any

import numpy as np

ENCODINGS = {  # encoding -> (numpy dtype, channels)
    "bgr8": (np.uint8, 3), "rgb8": (np.uint8, 3), "bgra8": (np.uint8, 4), "rgba8": (np.uint8, 4),
    "mono8": (np.uint8, 1), "mono16": (np.uint16, 1), "8UC1": (np.uint8, 1), "8UC3": (np.uint8, 3),
    "8UC4": (np.uint8, 4), "16UC1": (np.uint16, 1), "32FC1": (np.float32, 1), "64FC1": (np.float64, 1),
}
_ORDER = {"bgr8": "bgr", "rgb8": "rgb", "bgra8": "bgra", "rgba8": "rgba", "mono8": "m", "8UC3": "bgr",
          "8UC4": "bgra", "8UC1": "m"}


class CvBridgeError(TypeError):
    """A conversion cv_bridge cannot make (the message says which)."""


class CvBridge:
    def imgmsg_to_cv2(self, img_msg: Any, desired_encoding: str = "passthrough") -> np.ndarray:
        encoding = img_msg.encoding
        if encoding not in ENCODINGS:
            raise CvBridgeError(f"Unrecognized image encoding [{encoding}]")
        scalar, channels = ENCODINGS[encoding]
        dtype = np.dtype(scalar).newbyteorder(">" if img_msg.is_bigendian else "<")
        row = img_msg.width * channels * dtype.itemsize
        if img_msg.step < row or len(img_msg.data) < img_msg.step * img_msg.height:
            raise CvBridgeError(f"image data of {len(img_msg.data)} bytes is too short for {img_msg.height} rows of "
                                f"step {img_msg.step} ({img_msg.width} x {channels} x {dtype.itemsize} bytes)")
        rows = np.frombuffer(bytes(img_msg.data), dtype=np.uint8)[: img_msg.step * img_msg.height]
        rows = rows.reshape(img_msg.height, img_msg.step)[:, :row]
        image = np.ascontiguousarray(rows).view(dtype).astype(dtype.newbyteorder("="))
        image = image.reshape(img_msg.height, img_msg.width, channels) if channels > 1 else \
            image.reshape(img_msg.height, img_msg.width)
        if desired_encoding in ("passthrough", encoding):
            return image
        return _convert(image, encoding, desired_encoding)

    def cv2_to_imgmsg(self, cvim: np.ndarray, encoding: str = "passthrough", header: Any = None) -> Any:
        from sensor_msgs.msg import Image

        cvim = np.asarray(cvim)
        if encoding == "passthrough":
            encoding = {(np.uint8, 1): "8UC1", (np.uint8, 3): "8UC3", (np.uint8, 4): "8UC4",
                        (np.uint16, 1): "16UC1", (np.float32, 1): "32FC1", (np.float64, 1): "64FC1"}.get(
                (cvim.dtype.type, 1 if cvim.ndim == 2 else cvim.shape[2]), "")
            if not encoding:
                raise CvBridgeError(f"no encoding for an array of {cvim.dtype} with shape {cvim.shape}")
        if encoding not in ENCODINGS:
            raise CvBridgeError(f"Unrecognized image encoding [{encoding}]")
        dtype, channels = ENCODINGS[encoding]
        have = 1 if cvim.ndim == 2 else cvim.shape[2]
        if cvim.dtype != dtype or have != channels:
            raise CvBridgeError(f"encoding specified as {encoding}, but image has incompatible type "
                                f"{cvim.dtype} with {have} channel(s)")
        msg = Image(height=int(cvim.shape[0]), width=int(cvim.shape[1]), encoding=encoding, is_bigendian=0,
                    step=int(cvim.shape[1] * channels * cvim.dtype.itemsize),
                    data=np.ascontiguousarray(cvim).tobytes())
        if header is not None:
            msg.header = header
        return msg


def _convert(image: np.ndarray, source: str, target: str) -> np.ndarray:
    if source not in _ORDER or target not in _ORDER:
        raise CvBridgeError(f"cannot convert from [{source}] to [{target}]")
    have, want = _ORDER[source], _ORDER[target]
    if have == "m":
        planes = {c: image for c in "rgb"}
        planes["a"] = np.full_like(image, 255)
    else:
        planes = {c: image[..., have.index(c)] for c in have}
        planes.setdefault("a", np.full_like(image[..., 0], 255))
    if want == "m":
        grey = 0.299 * planes["r"] + 0.587 * planes["g"] + 0.114 * planes["b"]
        return np.clip(np.rint(grey), 0, 255).astype(np.uint8)
    return np.stack([planes[c] for c in want], axis=-1)
