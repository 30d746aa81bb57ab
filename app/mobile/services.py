"""The mobile world's services: recording it to MCAP (`hri-lab record` calls them, as it calls the
lifting lab's; the file: sim/mobile/recording.py), with the lifting lab's request and answer
types. Nothing else: the students' nodes bring their own services."""

from __future__ import annotations

import threading
import time
import traceback
from pathlib import Path

from sim.mobile.recording import MobileRecording

from app.lab.services import RecordingResponse, StartRecordingRequest
from app.ros.messages import Empty
from app.ros.services import Service, ServiceFailure, ServiceRegistry

POLL_PERIOD = 0.01  # s between two looks at the snapshot (the topics are sampled at 20 Hz, scans at 5 Hz)


class MobileRecorder:
    """Records the live mobile world from its snapshots in a thread of its own, until stopped."""

    def __init__(self, lab, path: Path, max_bytes: int) -> None:
        self.lab, self.path, self.max_bytes = lab, path, max_bytes
        self.recording = MobileRecording(path, lab.world.config, list(lab.topics))
        self.stopped: str | None = None
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="mobile-recorder", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        last = None
        try:
            with self.lab.needs(POLL_PERIOD):
                while not self._stop.wait(POLL_PERIOD):
                    snapshot = self.lab.snapshot()
                    if snapshot.time != last:
                        last = snapshot.time
                        self.recording.add(snapshot)
                    if self.path.stat().st_size > self.max_bytes:
                        self.stopped = f"recording stopped: the file reached its cap ({self.max_bytes / 2**20:.0f} MiB)"
                        return
        except Exception as exc:  # noqa: BLE001 - the file is finished whatever went wrong
            self.stopped = "recording failed: " + "".join(traceback.format_exception_only(exc)).strip()
        finally:
            self.recording.close()

    @property
    def running(self) -> bool:
        return self._thread.is_alive()

    def stop(self) -> str:
        self._stop.set()
        self._thread.join(timeout=10.0)
        self.recording.close()
        return self.stopped or ""


def start_recording(lab, request: StartRecordingRequest) -> RecordingResponse:
    """Record the mobile world to MCAP (/scan as foxglove.LaserScan, /tf, the arena, the topics)."""
    if lab.recorder is not None and lab.recorder.running:
        raise ServiceFailure(f"already recording to {lab.recorder.path}: call /stop_recording first")
    name = request.name or time.strftime("hri-lab_%Y%m%d_%H%M%S")
    path = Path(lab.recordings_dir) / (name if name.endswith(".mcap") else name + ".mcap")
    if path.exists():
        raise ServiceFailure(f"{path} exists: choose another name")
    try:
        lab.recorder = MobileRecorder(lab, path, int(request.max_mb * 2**20))
    except OSError as exc:
        raise ServiceFailure(f"cannot write {path}: {exc.strerror or exc}") from None
    lab.info("recorder", f"recording to {path}")
    return RecordingResponse(success=True, message=f"recording to {path}", path=str(path), messages=0, bytes=0)


def stop_recording(lab, request: Empty) -> RecordingResponse:
    recorder = lab.recorder
    if recorder is None:
        raise ServiceFailure("not recording: call /start_recording first")
    early = recorder.stop()
    lab.recorder = None
    size = recorder.path.stat().st_size
    message = (f"{early}; " if early else "") + (
        f"recorded {recorder.recording.messages} messages, {size / 2**20:.2f} MiB to {recorder.path}"
    )
    lab.info("recorder", message)
    return RecordingResponse(
        success=not early, message=message, path=str(recorder.path), messages=recorder.recording.messages, bytes=size
    )


SERVICES = ServiceRegistry(
    [
        Service(
            "/start_recording",
            "hri_lab/StartRecording",
            StartRecordingRequest,
            RecordingResponse,
            start_recording,
            "Record the mobile world to an MCAP file (like ros2 bag record): Foxglove's 3D panel shows its scan; "
            "hri-lab play replays it.",
        ),
        Service(
            "/stop_recording",
            "hri_lab/StopRecording",
            Empty,
            RecordingResponse,
            stop_recording,
            "Stop the recording and finish the file; download it with GET /recordings/NAME.",
        ),
    ]
)
