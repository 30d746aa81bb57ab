"""The camera's renderer in a process of its own (sim/camera_render.py): the 1 kHz loop never waits
for it and the server's Python never renders.

- The process is forked from the server at start and sleeps until somebody needs images: a
  subscriber holds `wants(period)` (a rosbridge subscription, an HTTP stream, a recording), an HTTP
  request for the latest image calls `lease()`; each writes a byte to the pipe the idle process
  waits on (a pipe, not a lock both sides take: a renderer killed at any moment cannot hold the
  server up). Idle, it wakes only every PARENT_CHECK_S (it looked at the demand every 20 ms before:
  ~0.5 % of a core in every idle lab). The OpenGL context and the meshes are made at the first
  demand (a second or two), then kept.
- While wanted it renders the latest snapshot (read from the simulation's shared memory, as every
  reader does) at the shortest period wanted, at most MAX_RATE_HZ, and publishes each image in
  shared memory (app/runtime/shared_frame.py) with the snapshot's simulated time.
- Its images are /image_raw's (IMAGE; `image_message` of a frame), whichever world has the camera.
- It runs at a lower priority (nice) than the server; should it die (a crash in the driver), the
  supervisor thread forks a new one. A renderer that cannot start (no EGL) says why in `error`.
"""

from __future__ import annotations

import math
import multiprocessing
import os
import select
import signal
import threading
import time
from collections import Counter
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from multiprocessing.process import BaseProcess

from sim import camera
from sim.camera_render import SceneSizes
from sim.messages import image
from sim.procedures.runner import die_with_parent  # imported here: a fork of a threaded server imports nothing new
from sim.world import Snapshot

from app.runtime.shared_frame import Frame, SharedFrame

_FORK = multiprocessing.get_context("fork")
IMAGE = "/image_raw"  # the camera's topic (sensor_msgs/Image)
MAX_RATE_HZ = 30.0  # images per second at most (a camera's usual rate)
PARENT_CHECK_S = 1.0  # s between two looks at the server (still our parent?) while nobody wants images
LEASE_S = 2.0  # s an HTTP request for the latest image keeps the renderer going
NICE = 5  # the renderer yields the CPU to the server (the loop runs real-time when it may)
ERROR_BYTES = 1024


def image_message(frame: Frame) -> dict:
    """/image_raw's message of a rendered frame: stamped with the simulated time of the pose it shows."""
    return image(frame.time, frame.image)


class CameraProcess:
    watch_period = 0.5  # s between the supervisor's looks at the process

    def __init__(self, snapshot: Callable[[], Snapshot], sizes: Callable[[], SceneSizes]) -> None:
        self._snapshot, self._sizes = snapshot, sizes
        width, height = camera.CAMERA_SIZE
        self.frames = SharedFrame(width, height)
        self._period = _FORK.RawValue("d", math.inf)  # the shortest period (s) a holder wants; inf: none
        self._lease_until = _FORK.RawValue("d", 0.0)  # time.monotonic() until which a lease wants images
        self._error = _FORK.RawArray("c", ERROR_BYTES)  # why the renderer could not start ("" when it did)
        self._wake_read = (
            self._wake_write
        ) = -1  # a pipe while started: wants() and lease() write, the idle process wakes
        self._wanted: Counter[float] = Counter()
        self._lock = threading.Lock()
        self._process: BaseProcess | None = None
        self._stop = threading.Event()
        self.restarts = 0

    # --- life cycle -------------------------------------------------------------------------
    def start(self) -> None:
        if self._process is None:
            with self._lock:
                self._wake_read, self._wake_write = os.pipe()
                for fd in (self._wake_read, self._wake_write):
                    os.set_blocking(fd, False)
            self._spawn()
            threading.Thread(target=self._watch, name="camera-supervisor", daemon=True).start()

    def _spawn(self) -> None:
        process = _FORK.Process(
            target=_child_main,
            args=(
                self._snapshot,
                self._sizes,
                self.frames,
                self._period,
                self._lease_until,
                self._error,
                self._wake_read,
            ),
            name="hri-lab-camera",
            daemon=True,
        )
        process.start()
        self._process = process

    def _watch(self) -> None:
        while not self._stop.wait(self.watch_period):
            process = self._process
            if process is not None and not process.is_alive() and not self._stop.is_set():
                self.restarts += 1
                self._spawn()

    def stop(self) -> None:
        self._stop.set()
        process, self._process = self._process, None
        if process is not None:
            process.terminate()
            process.join(timeout=2.0)
            if process.is_alive():
                process.kill()
                process.join(timeout=2.0)
        with self._lock:  # no wake-up is written to a descriptor number that another file may take next
            if self._wake_write >= 0:
                os.close(self._wake_read)
                os.close(self._wake_write)
                self._wake_read = self._wake_write = -1

    @property
    def pid(self) -> int | None:
        process = self._process
        return process.pid if process is not None else None

    @property
    def running(self) -> bool:
        process = self._process
        return process is not None and process.is_alive()

    # --- demand -----------------------------------------------------------------------------
    @contextmanager
    def wants(self, period: float) -> Iterator[None]:
        """While the block runs, somebody wants an image every `period` s (at most MAX_RATE_HZ)."""
        with self._lock:
            self._wanted[period] += 1
            self._period.value = min(self._wanted)
        self._wake()
        try:
            yield
        finally:
            with self._lock:
                self._wanted[period] -= 1
                if not self._wanted[period]:
                    del self._wanted[period]
                self._period.value = min(self._wanted, default=math.inf)

    def lease(self, seconds: float = LEASE_S) -> None:
        """Images wanted for the next `seconds` (at the full rate): an HTTP request for the latest one."""
        self._lease_until.value = max(self._lease_until.value, time.monotonic() + seconds)
        self._wake()

    def _wake(self) -> None:
        with self._lock:
            if self._wake_write < 0:  # not started, or stopped
                return
            try:
                os.write(self._wake_write, b"!")
            except BlockingIOError:  # full: wake-ups are waiting already
                pass

    @property
    def wanted(self) -> bool:
        return _period_wanted(self._period, self._lease_until) < math.inf

    # --- reading ----------------------------------------------------------------------------
    def latest(self) -> Frame | None:
        """The latest image, None before the first."""
        return self.frames.read()

    @property
    def number(self) -> int:
        """Images rendered so far (a new one came when this grew)."""
        return self.frames.number

    @property
    def error(self) -> str:
        """Why the renderer could not start ("" when it did or has not tried yet)."""
        return self._error.value.decode("utf-8", "replace")


def _period_wanted(period, lease_until) -> float:
    wanted = period.value
    if time.monotonic() < lease_until.value:
        wanted = min(wanted, 1.0 / MAX_RATE_HZ)
    return wanted


# --- the child ------------------------------------------------------------------------------
def _child_main(snapshot, sizes, frames: SharedFrame, period, lease_until, error, wake: int) -> None:
    """Render while wanted, idle otherwise, until the server is gone (or stops us)."""
    from app.runtime.process import close_inherited_sockets, name_this_process

    name_this_process("hri-lab-camera")
    close_inherited_sockets(keep=-1)
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl+C is the server's to handle; it stops us
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    try:
        os.nice(NICE)
    except OSError:
        pass
    parent = os.getppid()
    die_with_parent(parent)  # the server's death ends it at once, however long it sleeps
    renderer = None
    while os.getppid() == parent:
        wanted = _period_wanted(period, lease_until)
        if wanted == math.inf:
            _drain(wake)  # before the second look: a demand written after it is never missed
            if _period_wanted(period, lease_until) == math.inf:
                select.select([wake], [], [], PARENT_CHECK_S)
            continue
        if renderer is None:
            try:
                from sim.camera_render import CameraRenderer

                renderer = CameraRenderer(sizes())
                error.value = b""
            except Exception as exc:  # noqa: BLE001 - said to whoever asks for an image; tried again later
                error.value = f"the camera's renderer could not start: {type(exc).__name__}: {exc}".encode()[
                    : ERROR_BYTES - 1
                ]
                time.sleep(1.0)
                continue
        started = time.monotonic()
        s = snapshot()
        posed_at = time.time()
        image = renderer.render(s)
        frames.write(image, s.time, posed_at, time.monotonic() - started)
        time.sleep(max(0.0, started + max(wanted, 1.0 / MAX_RATE_HZ) - time.monotonic()))


def _drain(fd: int) -> None:
    """Read every byte waiting in the wake-up pipe."""
    try:
        while os.read(fd, 4096):
            pass
    except BlockingIOError:
        pass
