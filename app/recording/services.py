"""The recording services every world serves alike: /start_recording and /stop_recording
(`hri-lab record` calls them), a world bringing its recorder (the lifting lab's: app/lab/recorder.py,
the mobile world's: app/mobile/services.py)."""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any, Protocol

from pydantic import Field

from app.ros.messages import Bool, Empty, Int64, RosMessage, RosType, String
from app.ros.services import Service, ServiceFailure

DEFAULT_DIR = Path("recordings")  # where /start_recording writes (serve --output-dir DIR: DIR/recordings)


class StartRecordingRequest(RosMessage):
    name: Annotated[
        str,
        Field(pattern=r"^([A-Za-z0-9_-][A-Za-z0-9_.-]{0,63})?$"),
        RosType("string", "file name in the server's recordings folder; '' = hri-lab_<date>_<time>"),
    ] = ""
    max_mb: Annotated[
        float,
        Field(gt=0.0, le=10240.0, allow_inf_nan=False),
        RosType("float64", "size cap (MiB): the recording stops there"),
    ] = 1024.0


class RecordingResponse(RosMessage):
    success: Bool
    message: String
    path: String  # on the server; download: GET /recordings/NAME
    messages: Int64
    bytes: Int64


class File(Protocol):
    @property
    def messages(self) -> int: ...  # written so far


class Recorder(Protocol):
    """A live recording in a thread of its own, until stopped."""

    path: Path

    @property
    def recording(self) -> File: ...

    @property
    def running(self) -> bool: ...

    @property
    def size(self) -> int: ...  # bytes in the file

    def stop(self) -> str: ...  # stop and finish the file; why it had stopped before, if it had


def start(
    lab: Any, request: StartRecordingRequest, recorder: Callable[[Any, Path, int], Recorder]
) -> RecordingResponse:
    """A new recording of `lab` by `recorder(lab, path, max_bytes)`, in the lab's recordings folder."""
    if lab.recorder is not None and lab.recorder.running:
        raise ServiceFailure(f"already recording to {lab.recorder.path}: call /stop_recording first")
    name = request.name or time.strftime("hri-lab_%Y%m%d_%H%M%S")
    path = Path(lab.recordings_dir) / (name if name.endswith(".mcap") else name + ".mcap")
    if path.exists():
        raise ServiceFailure(f"{path} exists: choose another name")
    try:
        lab.recorder = recorder(lab, path, int(request.max_mb * 2**20))
    except OSError as exc:
        raise ServiceFailure(f"cannot write {path}: {exc.strerror or exc}") from None
    lab.info("recorder", f"recording to {path}")
    return RecordingResponse(success=True, message=f"recording to {path}", path=str(path), messages=0, bytes=0)


def stop_recording(lab: Any, request: Empty) -> RecordingResponse:
    """/stop_recording: the file finished, what it holds."""
    recorder = lab.recorder
    if recorder is None:
        raise ServiceFailure("not recording: call /start_recording first")
    early = recorder.stop()
    lab.recorder = None
    size = recorder.size
    message = (f"{early}; " if early else "") + (
        f"recorded {recorder.recording.messages} messages, {size / 2**20:.2f} MiB to {recorder.path}"
    )
    lab.info("recorder", message)
    return RecordingResponse(
        success=not early, message=message, path=str(recorder.path), messages=recorder.recording.messages, bytes=size
    )


def services(recorder: Callable[[Any, Path, int], Recorder], started: str, finished: str = "") -> list[Service]:
    """/start_recording with `recorder`, /stop_recording: a world's entries of its service table;
    `started` says what is recorded and what opens the file, `finished` what the finished file holds."""

    def start_recording(lab: Any, request: StartRecordingRequest) -> RecordingResponse:
        return start(lab, request, recorder)

    return [
        Service(
            "/start_recording",
            "hri_lab/StartRecording",
            StartRecordingRequest,
            RecordingResponse,
            start_recording,
            f"Record {started}",
        ),
        Service(
            "/stop_recording",
            "hri_lab/StopRecording",
            Empty,
            RecordingResponse,
            stop_recording,
            f"Stop the recording and finish the file{finished}; download it with GET /recordings/NAME.",
        ),
    ]
