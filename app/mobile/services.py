"""The mobile world's services: recording it to MCAP (`hri-lab record` calls them, as it calls the
lifting lab's; the file: sim/mobile/recording.py), the services every world serves alike
(app/recording/services.py) with its recorder. Nothing else: the students' nodes bring their own services."""

from __future__ import annotations

import threading
import traceback
from pathlib import Path

from sim.mobile.recording import MobileRecording

from app.recording import services as recording
from app.ros.services import ServiceRegistry

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

    @property
    def size(self) -> int:
        return self.path.stat().st_size

    def stop(self) -> str:
        self._stop.set()
        self._thread.join(timeout=10.0)
        self.recording.close()
        return self.stopped or ""


SERVICES = ServiceRegistry(
    recording.services(  # /scan as foxglove.LaserScan, /tf, the arena, the topics
        MobileRecorder,
        "the mobile world to an MCAP file (like ros2 bag record): Foxglove's 3D panel shows its scan; "
        "hri-lab play replays it.",
    )
)
