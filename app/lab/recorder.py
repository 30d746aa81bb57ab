"""Recording the live lab (`/start_recording`, `/stop_recording`, `hri-lab record`).

A thread of the server process reads the loop's snapshot from shared memory every POLL_PERIOD
(reading never touches the 1 kHz loop, which runs in its own process) and hands it to a
sim.recording Recording, which keeps the topics every 10 ms (100 Hz) and /tf + /scene every
40 ms (25 Hz) of simulated time. Log times are the wall clock (what `ros2 bag record` stamps);
the messages' header stamps are the simulated time. The file is finished (index, summary) on
stop, on the server's shutdown and when the thread fails; a size cap (max_mb) or a free-disk
floor stops it with a message; a file cut short by a crash of the server is still readable.

The camera's images go in too (/image_raw/compressed, JPEG, every IMAGE_PERIOD of simulated time):
the recording wants them from the camera process while it runs (docs/camera.md).
"""

from __future__ import annotations

import threading
import time
import traceback
from pathlib import Path

import cv2

from sim.camera import OPTICAL_FRAME
from sim.recording.writer import MIN_FREE_BYTES, Recording
from sim.sampling import due

from app.lab import commands

POLL_PERIOD = 0.005  # s between two reads of the snapshot (every new 10 ms sample is seen)
IMAGE_PERIOD = 0.1  # s of simulated time between two recorded images (10 Hz)
JPEG_QUALITY = 85


class LiveRecorder:
    def __init__(self, lab, path: Path, max_bytes: int, min_free_bytes: int = MIN_FREE_BYTES) -> None:
        self.lab = lab
        self.path = path
        self.recording = Recording(
            path, lab.call(commands.world_config), source="live", max_bytes=max_bytes, min_free_bytes=min_free_bytes
        )
        self.started = time.time()
        self.failure: str | None = None
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="recorder", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        try:
            with self.lab.needs(POLL_PERIOD), self.lab.camera.wants(IMAGE_PERIOD):
                self._record_each_new_state()
        except Exception as exc:  # noqa: BLE001 - the file is finished whatever went wrong
            self.failure = "recording failed: " + "".join(traceback.format_exception_only(exc)).strip()
            self.lab.info("recorder", self.failure)
        finally:
            self.recording.close({"failure": self.failure} if self.failure else None)

    def _record_each_new_state(self) -> None:
        last = None
        camera, seen_image, last_image = self.lab.camera, self.lab.camera.number, None
        while not self._stop.wait(POLL_PERIOD):
            if camera.number != seen_image:
                frame = camera.latest()
                if frame is not None and due(last_image, frame.time, IMAGE_PERIOD):
                    seen_image, last_image = frame.number, frame.time
                    ok, jpeg = cv2.imencode(".jpg", frame.image, [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY])
                    if ok:
                        self.recording.add_image(frame.time, jpeg.tobytes(), OPTICAL_FRAME, log_time=time.time_ns())
            snapshot = self.lab.snapshot()
            if snapshot.time == last:
                continue
            last = snapshot.time
            if not self.recording.add(snapshot, log_time=time.time_ns()):
                self.lab.info("recorder", self.recording.stopped or "recording stopped")
                return

    @property
    def running(self) -> bool:
        return self._thread.is_alive()

    @property
    def size(self) -> int:
        return self.recording.size

    def stop(self) -> str:
        """Stop and finish the file; why it had stopped before, if it had."""
        self._stop.set()
        self._thread.join(timeout=10.0)
        self.recording.close()
        return self.failure or self.recording.stopped or ""
