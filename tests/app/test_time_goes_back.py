"""Time may go back (sim/sampling.py): after a reset of either world, at a random moment, every live
stream goes on with the new trial's messages — HTTP topic streams, rosbridge subscriptions at every
throttle (the F_ext ring's every step and a snapshot topic's), the camera's images, a live
recording — instead of going silent until the simulated time climbs back past where it was.

Each subscriber keeps the stamps it got, in order. A reset shows in them as a stamp earlier than
the one before, and the first of the new trial comes before the new trial's time reaches the old
one's (the code before sent nothing until then, and then went on with no stamp going back). How
much before is the machine's speed (a camera's frame under load), so it is not asserted."""

from __future__ import annotations

import random
import threading
from contextlib import ExitStack
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from sim.mobile.world import MobileConfig
from sim.recording.reader import messages

from app.mobile.lab import MobileLab
from app.mobile.world import MOBILE
from app.serving.compose import create_app
from tests.waiting import wait_for


def _stamp_s(message: dict) -> float:
    stamp = message["header"]["stamp"]
    return stamp["sec"] + stamp["nanosec"] * 1e-9


DRAINED = "drained"  # the id of the call a rosbridge subscriber ends with: its answer comes after the last message


class Subscriber(threading.Thread):
    """One live stream, read on a thread of its own: the stamps it got, in order.

    In-process (FastAPI's TestClient) a socket has no backpressure: what the lab sent waits in the
    client's queue however far behind this thread is (a 1 kHz stream on a loaded machine: seconds), so
    a rosbridge stream is ended by unsubscribing and a call whose answer comes after its last
    message, and read to that answer; an HTTP stream (a few messages a second) is read until told."""

    def __init__(self, name: str, ws, message_of=lambda frame: frame, topic: str | None = None) -> None:
        super().__init__(daemon=True, name=name)
        self.ws, self.message_of, self.topic = ws, message_of, topic
        self.stamps: list[float] = []
        self.stop = threading.Event()
        self.error: BaseException | None = None

    def finish(self) -> None:
        """No more messages wanted: the reader ends once it has read what the lab sent before."""
        self.stop.set()
        if self.topic is not None:  # rosbridge: its own unsubscribe, then the marker
            self.ws.send_json({"op": "unsubscribe", "topic": self.topic})
            self.ws.send_json({"op": "call_service", "service": "/rosapi/get_time", "id": DRAINED})

    def run(self) -> None:
        try:
            while self.topic is not None or not self.stop.is_set():
                frame = self.ws.receive_json()
                if frame.get("op") == "service_response" and frame.get("id") == DRAINED:
                    return
                message = self.message_of(frame)
                if message is not None:
                    self.stamps.append(_stamp_s(message))
        except BaseException as exc:  # noqa: BLE001 - an HTTP stream's socket closed at the end, or a failure
            if self.topic is not None or not self.stop.is_set():
                self.error = exc

    def trials(self) -> list[list[float]]:
        """The stamps split where time went back: one list per trial seen."""
        split: list[list[float]] = [[]]
        for stamp in self.stamps:
            if split[-1] and stamp < split[-1][-1]:
                split.append([])
            split[-1].append(stamp)
        return split


def _rosbridge(client: TestClient, stack, topic: str, throttle_ms: int, queue_length: int = 1):
    ws = stack.enter_context(client.websocket_connect("/"))
    ws.send_json({"op": "subscribe", "topic": topic, "throttle_rate": throttle_ms, "queue_length": queue_length})
    return Subscriber(
        f"rosbridge {topic} @{throttle_ms} ms", ws, lambda f: f.get("msg") if f.get("op") == "publish" else None, topic
    )


def _http(client: TestClient, stack, topic: str, rate_hz: float):
    ws = stack.enter_context(client.websocket_connect(f"/topics{topic}/stream?rate={rate_hz}"))
    return Subscriber(f"HTTP {topic} @{rate_hz} Hz", ws)


def _run_trials(sim_time, reset, subscribers: list[Subscriber], rng: random.Random) -> list[float]:
    """Once every stream is live, two resets at random moments (the first a few s of simulated time
    later, the second early in the next trial); then the third trial runs past the first's time.
    The old trials' lengths (s)."""
    for s in subscribers:
        s.start()
    for s in subscribers:  # every stream live (the camera's renderer takes a while to start)
        wait_for(lambda s=s: s.stamps or s.error, timeout=120)
    lengths = []
    for low, high in ((3.0, 4.0), (0.5, 1.5)):
        at = (sim_time() if not lengths else 0.0) + rng.uniform(low, high)
        wait_for(lambda at=at: sim_time() >= at, timeout=120)
        lengths.append(sim_time())
        reset()
        wait_for(lambda: sim_time() < lengths[-1], timeout=60)  # the reset happened
    wait_for(lambda: sim_time() >= lengths[0] + 0.5, timeout=120)
    for s in subscribers:
        s.finish()
    for s in subscribers:  # before their sockets close
        s.join(timeout=120)
    return lengths


def _assert_each_went_on(subscribers: list[Subscriber], lengths: list[float], seed: int) -> None:
    for s in subscribers:
        assert not s.is_alive(), f"{s.name}: its reader did not end"
        assert s.error is None, f"{s.name}: {s.error!r}"
        trials = s.trials()
        assert len(trials) >= 3, (
            f"{s.name}: time went back {len(trials) - 1} time(s) in what it got, not 2 (seed {seed}): "
            f"{len(s.stamps)} messages, stamps {s.stamps[:3]} ... {s.stamps[-3:]}"
        )
        first_after_long_trial = trials[-2][0]
        assert first_after_long_trial < lengths[0], (
            f"{s.name}: the first message after a reset at t = {lengths[0]:.2f} s came at "
            f"{first_after_long_trial:.3f} s (seed {seed})"
        )
        assert len(trials[-1]) >= 2, f"{s.name}: the last trial's stream did not go on (seed {seed}): {trials[-1]}"


@pytest.fixture(scope="module")
def recordings(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("recordings")


def test_every_stream_of_the_lifting_lab_goes_on_after_resets_at_random_moments(client, lab, recordings):
    rng = random.Random()
    seed = rng.randrange(1 << 30)
    rng.seed(seed)
    lab.recordings_dir = recordings
    with ExitStack() as stack:
        subscribers = [
            _rosbridge(client, stack, "/franka_state_controller/F_ext", 0),  # every step's, from the ring
            _rosbridge(client, stack, "/franka_state_controller/F_ext", 100),
            _rosbridge(client, stack, "/joint_states", 50),
            _rosbridge(client, stack, "/image_raw", 200),
            _http(client, stack, "/joint_states", 10),
            _http(client, stack, "/image_raw", 4),
        ]
        started = client.post("/services/start_recording", json={})
        assert started.status_code == 200, started.text

        def reset() -> None:
            assert client.post("/services/reset_simulation", json={}).json()["success"]

        lengths = _run_trials(lambda: lab.snapshot().time, reset, subscribers, rng)
        stopped = client.post("/services/stop_recording", json={})
        assert stopped.status_code == 200, stopped.text
    _assert_each_went_on(subscribers, lengths, seed)

    (path,) = recordings.glob("*.mcap")
    recorded = list(messages(path))
    joint_states = [_stamp_s(m.data) for m in recorded if m.topic == "/joint_states"]
    images = [
        m.data["timestamp"]["sec"] + m.data["timestamp"]["nsec"] * 1e-9
        for m in recorded
        if m.topic.startswith("/image_raw")
    ]
    for name, stamps in (("recorded /joint_states", joint_states), ("recorded images", images)):
        backs = [i for i in range(1, len(stamps)) if stamps[i] < stamps[i - 1]]
        assert len(backs) >= 2, f"{name}: the recording did not go on after each reset (seed {seed})"
        assert stamps[backs[0]] < lengths[0], f"{name} (seed {seed})"


def test_every_stream_of_the_mobile_lab_goes_on_after_resets_at_random_moments():
    rng = random.Random()
    seed = rng.randrange(1 << 30)
    rng.seed(seed)
    with TestClient(create_app(MOBILE, MobileLab(MobileConfig()))) as client, ExitStack() as stack:
        lab = client.app.state.lab
        subscribers = [
            _rosbridge(client, stack, "/scan", 0),
            _rosbridge(client, stack, "/odom", 100),
            _http(client, stack, "/odom", 10),
        ]

        def reset() -> None:
            assert client.post("/mobile/reset").status_code == 200

        lengths = _run_trials(lambda: lab.snapshot().time, reset, subscribers, rng)
    _assert_each_went_on(subscribers, lengths, seed)
