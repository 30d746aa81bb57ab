"""/camera: the camera's latest image for a browser (PNG or JPEG) and the windows `cv2.imshow` of
students' programs opened (docs/camera.md).

The image is the one /image_raw carries (app/runtime/camera_process.py renders it): a request
keeps the renderer going for a moment (`lease`), so a page that polls the image gets fresh ones
and the renderer stops soon after the page goes. The first image after a long idle takes the
renderer's start (a second or two): the request waits for it, at most WAIT_S.
"""

from __future__ import annotations

import base64
import binascii
import time
from typing import Literal

import cv2
from fastapi import APIRouter, HTTPException, Query, Request
from fastapi.responses import Response

from app.api.deps import LabDep
from app.runtime.camera_process import MAX_RATE_HZ
from app.runtime.shared_frame import Frame
from interfaces.image_windows import WINDOWS

WAIT_S = 30.0  # s a request waits for an image (the renderer's start on a loaded machine)
POLL_S = 0.005
FRESH_S = 2.0 / MAX_RATE_HZ  # an image whose pose is at most this old (wall clock) is current
MEDIA = {"png": "image/png", "jpg": "image/jpeg"}


def current_frame(lab, wait_s: float = WAIT_S) -> Frame:
    """The camera's image of the current pose (waits for the renderer, in a worker thread);
    HTTPException 503 when none came in wait_s (with the renderer's error when it has one)."""
    camera = lab.camera
    asked = time.time()
    end = time.monotonic() + wait_s
    while time.monotonic() < end:
        camera.lease()
        frame = camera.latest()
        if frame is not None and frame.posed_at >= asked - FRESH_S:
            return frame
        if camera.error:
            break
        time.sleep(POLL_S)
    raise HTTPException(503, camera.error or f"the camera gave no image in {wait_s:g} s; ask again")


def encode(frame: Frame, kind: str, quality: int = 90) -> bytes:
    """The frame as PNG or JPEG bytes (OpenCV's encoders)."""
    params = [cv2.IMWRITE_JPEG_QUALITY, quality] if kind == "jpg" else []
    ok, data = cv2.imencode(f".{kind}", frame.image, params)
    if not ok:  # pragma: no cover - OpenCV encodes any 8-bit BGR image
        raise HTTPException(500, f"the image could not be encoded as {kind}")
    return data.tobytes()


router = APIRouter(tags=["camera"])


@router.get(
    "/camera/image.{kind}",
    summary="The camera's latest image (what /image_raw carries) as PNG or JPEG",
    response_class=Response,
    responses={200: {"content": {"image/png": {}, "image/jpeg": {}}, "description": "the image"}},
)
def image(
    kind: Literal["png", "jpg"],
    lab: LabDep,
    quality: int = Query(90, ge=1, le=100, description="JPEG quality (1-100)"),
) -> Response:
    frame = current_frame(lab)
    return Response(
        encode(frame, kind, quality),
        media_type=MEDIA[kind],
        headers={"Cache-Control": "no-store", "X-Stamp": f"{frame.time:.6f}"},
    )


@router.get("/camera/windows", summary="The windows programs opened with cv2.imshow (newest image each)")
def windows(request: Request) -> list[dict]:
    """One entry per window: its name (cv2.imshow's), the topic its images come on (WINDOWS + the
    name as a ROS name) and the stamp (wall clock) of its newest image."""
    shown = request.app.state.bridge.windows.shown()
    return [
        {
            "name": msg.get("header", {}).get("frame_id", topic[len(WINDOWS) :]),
            "topic": topic,
            "id": topic[len(WINDOWS) :],
            "stamp": msg.get("header", {}).get("stamp", {}),
        }
        for topic, msg in sorted(shown.items())
    ]


@router.get(
    "/camera/windows/{window}.jpg",
    summary="A cv2.imshow window's newest image (JPEG)",
    response_class=Response,
    responses={200: {"content": {"image/jpeg": {}}, "description": "the image"}},
)
def window_image(window: str, request: Request) -> Response:
    msg = request.app.state.bridge.windows.get(WINDOWS + window)
    if msg is None:
        raise HTTPException(404, f"no window '{window}' (GET /camera/windows lists them)")
    try:
        data = base64.b64decode(msg.get("data", ""), validate=True)
    except (binascii.Error, TypeError, ValueError):
        raise HTTPException(404, f"window '{window}': its image is not base64 JPEG") from None
    return Response(data, media_type="image/jpeg", headers={"Cache-Control": "no-store"})
