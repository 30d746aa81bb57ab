"""`hri-lab bag record` and `hri-lab bag play`: rosbag's recorder and player as rosbridge clients.

Like rosbag's, each is a node of the lab's graph (a rosbridge v2 client on the lab's endpoint):

- **record** subscribes to the topics named (or every topic with `-a`, new ones as they appear,
  less `-x REGEX`; `-e REGEX` picks by pattern) at rosbridge's pass-through (every message) and
  writes a rosbag2 (MCAP, CDR, metadata.yaml; app/recording/bags.py). Each topic's definition:
  ROS 2's standard types from `rosbags`, the lab's and the workspace's from their .msg files
  (rosclient/share, the current folder's packages), a program's own from the full text it
  carried when it advertised (rosapi's topics_and_raw_types).
- **play** advertises every recorded topic and publishes its messages at their recorded times
  (scaled by `-r`, from `-s` seconds in, looped with `-l`, `/clock` with `--clock`), so programs
  under `hri-lab run`, roslibpy and roslibjs receive them as if live. A topic the live simulation
  publishes is skipped with a warning (the lab's own stays the lab's); a lab started with
  `hri-lab serve --replay` publishes none, so every recorded topic plays.
"""

from __future__ import annotations

import json
import re
import signal
import sys
import time
from collections import deque
from collections.abc import Callable, Iterator
from pathlib import Path
from types import FrameType
from urllib.parse import urlsplit

from websockets.exceptions import WebSocketException
from websockets.sync.client import ClientConnection, connect

from sim.recording.reader import RecordingError

from app.cli import client as c
from app.recording import bags
from app.rosbridge.protocol import MAX_FRAME as MAX_FRAME_CHARS  # the lab's limit on one frame

LAB_NODE_TOPICS = "/rosapi/node_details"
DISCOVERY_PERIOD_S = 1.0  # -a, -e: how often new topics are looked for
CLOCK_PERIOD_S = 0.01  # --clock: /clock at 100 Hz of bag time (ros2 bag play's --clock default is 40 Hz)
CLOCK_TYPE = "rosgraph_msgs/Clock"
MAX_PENDING = 10_000  # frames held while a service's answer is awaited


class Bridge:
    """A blocking rosbridge v2 connection: send frames, call services, receive publishes."""

    def __init__(self, url: str) -> None:
        parts = urlsplit(url)
        scheme = {"http": "ws", "https": "wss"}.get(parts.scheme, parts.scheme)
        token = c.os.environ.get("HRI_LAB_TOKEN")
        headers = {"Authorization": f"Bearer {token}"} if token else None
        try:
            self.ws: ClientConnection = connect(
                f"{scheme}://{parts.netloc}/", additional_headers=headers, max_size=None, open_timeout=10
            )
        except (OSError, WebSocketException) as exc:
            raise c.CliError(f"cannot reach the hri-lab server at {url}: {exc}") from None
        # frames received while waiting for a service's answer, the newest MAX_PENDING (a recorder
        # that falls behind loses the oldest, as rosbag's bounded buffer does)
        self.pending: deque[dict] = deque(maxlen=MAX_PENDING)
        self._id = 0

    def send(self, frame: dict) -> None:
        self.ws.send(json.dumps(frame, separators=(",", ":")))

    def call(self, service: str, args: dict | None = None, timeout: float = 10.0) -> dict:
        self._id += 1
        wanted = f"bag:{self._id}"
        self.send({"op": "call_service", "id": wanted, "service": service, "args": args or {}})
        end = time.monotonic() + timeout
        while True:
            left = end - time.monotonic()
            frame = self._read(left) if left > 0 else None
            if frame is None:
                raise c.CliError(f"{service}: no answer in {timeout:.0f} s")
            if frame.get("op") == "service_response" and frame.get("id") == wanted:
                if not frame.get("result", False):
                    raise c.CliError(f"{service}: {frame.get('values')}")
                return frame.get("values") or {}
            self.pending.append(frame)

    def receive(self, timeout: float) -> dict | None:
        """The next frame: one that came while a service was called first, else the socket's."""
        if self.pending:
            return self.pending.popleft()
        return self._read(timeout)

    def _read(self, timeout: float) -> dict | None:
        try:
            text = self.ws.recv(timeout=timeout)
        except TimeoutError:
            return None
        return json.loads(text)

    def close(self) -> None:
        self.ws.close()


def _stop_on_sigterm() -> None:
    """SIGTERM ends a recording or a playback as Ctrl+C does: the bag is finished, the summary printed."""

    def interrupt(signum: int, frame: FrameType | None) -> None:
        raise KeyboardInterrupt

    signal.signal(signal.SIGTERM, interrupt)


# --- record -------------------------------------------------------------------------------------
def _definition_finder() -> Callable[[str], str | None]:
    """The .msg files a program's imports would find: the current folder's workspace, then the
    definitions the lab ships (interfaces/share, its own hri_lab package's included)."""
    from interfaces.packages import Interfaces, full_text
    from rosclient.interfaces import workspace_roots

    found = Interfaces(workspace_roots(Path.cwd() / "bag"))

    def definition(type_name: str) -> str | None:
        try:
            return full_text(found.message(type_name))
        except (ImportError, OSError, ValueError, RecursionError):
            return None

    return definition


def chosen(topics: dict[str, str], args) -> list[str]:
    """The topics to record now: those named, or all (-a) / matching -e, less -x."""
    include = re.compile(args.regex) if args.regex else None
    exclude = re.compile(args.exclude) if args.exclude else None
    named = {"/" + t.strip("/") for t in args.topics}
    out = []
    for topic in topics:
        if topic in named or args.all or (include is not None and include.search(topic)):  # noqa: SIM102 - two conditions kept apart, each with its own comment
            if exclude is None or not exclude.search(topic):
                out.append(topic)
    return out


def record(args) -> int:
    if not args.topics and not args.all and not args.regex:
        raise c.CliError("name the topics to record, or -a for all of them (-e REGEX for those matching)")
    for flag, pattern in (("-e", args.regex), ("-x", args.exclude)):
        if pattern:
            try:
                re.compile(pattern)
            except re.error as exc:
                raise c.CliError(f"{flag} {pattern!r}: not a regular expression ({exc})") from None
    output = Path(args.output_name or time.strftime("rosbag2_%Y_%m_%d-%H_%M_%S"))
    if output.suffix in (".bag", ".mcap", ".db3"):
        output = output.with_suffix("")
    if output.exists():
        raise c.CliError(f"{output} exists: choose another name with -O")
    if not args.max_mb > 0:
        raise c.CliError(f"--max-mb {args.max_mb}: the cap must be a positive number of MiB")
    _stop_on_sigterm()
    bridge = Bridge(args.url)  # the lab first: no bag folder is left when it cannot be reached
    try:
        writer = bags.BagWriter(output, int(min(args.max_mb, 2**40) * 2**20))
    except RecordingError as exc:
        bridge.close()
        raise c.CliError(str(exc)) from None
    definition = _definition_finder()
    subscribed: set[str] = set()

    def discover() -> None:
        found = bridge.call("/rosapi/topics_and_raw_types")
        texts = dict(zip(found.get("topics", []), found.get("typedefs_full_text", [])))
        types = dict(zip(found.get("topics", []), found.get("types", [])))
        for topic in chosen(types, args):
            if topic in subscribed:
                continue
            type_name = types[topic]
            try:
                writer.add_topic(topic, type_name, definition(type_name) or texts.get(topic) or None)
            except RecordingError as exc:
                print(f"[WARN] {topic} not recorded: {exc}", file=sys.stderr, flush=True)
                subscribed.add(topic)
                continue
            bridge.send({"op": "subscribe", "topic": topic, "type": type_name, "queue_length": 1000})
            subscribed.add(topic)
            print(f"[INFO] Subscribed to topic '{topic}' ({type_name})", file=sys.stderr, flush=True)

    stopped = ""
    try:
        discover()
        for topic in {"/" + t.strip("/") for t in args.topics} - subscribed:
            print(f"[WARN] {topic} is not published yet: recorded once it is", file=sys.stderr, flush=True)
        print(f"[INFO] Recording to '{output}'; press Ctrl+C to stop", file=sys.stderr, flush=True)
        end = time.monotonic() + args.duration if args.duration else None
        next_discovery = time.monotonic() + DISCOVERY_PERIOD_S
        while end is None or time.monotonic() < end:
            now = time.monotonic()
            if now >= next_discovery and (args.all or args.regex or len(subscribed) < len(args.topics)):
                try:
                    discover()
                except c.CliError as exc:  # a busy lab: look again at the next period
                    print(f"[WARN] looking for new topics: {exc}", file=sys.stderr, flush=True)
                next_discovery = time.monotonic() + DISCOVERY_PERIOD_S
            frame = bridge.receive(0.1 if end is None else max(0.0, min(0.1, end - now)))
            if frame is None or frame.get("op") != "publish" or not writer.has(frame.get("topic", "")):
                continue
            try:
                if not writer.write(frame["topic"], time.time_ns(), frame.get("msg") or {}):
                    stopped = writer.stopped or ""
                    break
            except RecordingError as exc:
                print(f"[WARN] a message on {frame['topic']} not recorded: {exc}", file=sys.stderr, flush=True)
    except KeyboardInterrupt:
        pass
    except (OSError, WebSocketException) as exc:
        stopped = f"the lab went away: {exc}"
    finally:
        writer.close()
        try:
            bridge.close()
        except (OSError, WebSocketException):
            pass
    if stopped:
        print(f"[WARN] {stopped}", file=sys.stderr)
    counts = ", ".join(f"{t} {n}" for t, n in writer.counts.items())
    print(f"[INFO] {sum(writer.counts.values())} messages ({counts})", file=sys.stderr)
    print(output)
    return 0


# --- play ---------------------------------------------------------------------------------------
def timeline(
    messages: Iterator[bags.BagMessage], first: int, rate: float, start_s: float
) -> Iterator[tuple[float, bags.BagMessage]]:
    """(s after the play's start, message) of each message from `start_s` s after the bag's first
    one (`first`, ns): its recorded gap from the first played one divided by the rate."""
    played0 = None
    for m in messages:
        if (m.log_time - first) / 1e9 < start_s - 1e-9:
            continue
        played0 = m.log_time if played0 is None else played0
        yield (m.log_time - played0) / 1e9 / rate, m


def play(args) -> int:
    if args.rate <= 0 or args.rate != args.rate or args.rate == float("inf"):
        raise c.CliError(f"-r {args.rate}: the rate must be a positive number")
    if args.start < 0:
        raise c.CliError(f"-s {args.start}: the start must be >= 0 s")
    try:
        bag = bags.open_bag(args.file)
    except RecordingError as exc:
        raise c.CliError(str(exc)) from None
    info = bag.info()
    wanted = ["/" + t.strip("/") for t in args.topics] if args.topics else None
    playable = {t: ty for t, ty in bag.types.items() if bags._TYPE.match(ty) and (wanted is None or t in wanted)}
    if wanted is not None:
        for t in set(wanted) - set(bag.types):
            print(f"[WARN] {t} is not in the bag", file=sys.stderr, flush=True)
    _stop_on_sigterm()
    bridge = Bridge(args.url)
    lab_topics = set(bridge.call(LAB_NODE_TOPICS, {"node": _lab_node(bridge)}).get("publishing", []))
    for topic in sorted(set(playable) & lab_topics):
        print(
            f"[WARN] {topic} is published by the lab's simulation: not played (start the lab with "
            "`hri-lab serve --replay` to play it)",
            file=sys.stderr,
            flush=True,
        )
        del playable[topic]
    if not playable:
        bridge.close()
        raise c.CliError(f"{bag.path}: nothing to play (topics: {', '.join(bag.types) or 'none'})")
    for topic, type_name in playable.items():
        bridge.send({"op": "advertise", "topic": topic, "type": bags.ros1_type(type_name)})
    if args.clock:
        bridge.send({"op": "advertise", "topic": "/clock", "type": CLOCK_TYPE})
    print(
        f"[INFO] Playing {bag.path} ({info.storage}, {info.duration:.2f} s) at {args.rate:g}x: "
        f"{', '.join(playable)}{'; looping' if args.loop else ''}; press Ctrl+C to stop",
        file=sys.stderr,
        flush=True,
    )
    sent = skipped = 0
    try:
        time.sleep(0.2)  # advertisements in place before the first message (rosbag play's delay)
        while True:
            wall0, last_clock = time.monotonic(), None
            for offset, m in timeline(bag.messages(list(playable)), info.start, args.rate, args.start):
                wait = wall0 + offset - time.monotonic()
                if wait > 0:
                    _drain(bridge, wait)
                if args.clock and (last_clock is None or m.log_time - last_clock >= CLOCK_PERIOD_S * 1e9):
                    last_clock = m.log_time
                    sec, nanosec = divmod(m.log_time, 1_000_000_000)
                    bridge.send(
                        {"op": "publish", "topic": "/clock", "msg": {"clock": {"sec": sec, "nanosec": nanosec}}}
                    )
                text = json.dumps({"op": "publish", "topic": m.topic, "msg": m.data}, separators=(",", ":"))
                if len(text) > MAX_FRAME_CHARS:
                    skipped += 1
                    continue
                bridge.ws.send(text)
                sent += 1
            if not args.loop:
                break
    except KeyboardInterrupt:
        pass
    except RecordingError as exc:
        raise c.CliError(str(exc)) from None
    except (OSError, WebSocketException) as exc:
        raise c.CliError(f"the lab went away: {exc}") from None
    finally:
        try:
            bridge.close()
        except (OSError, WebSocketException):
            pass
    note = f" ({skipped} over the lab's frame limit of {MAX_FRAME_CHARS} characters skipped)" if skipped else ""
    print(f"[INFO] {sent} messages published{note}", file=sys.stderr)
    return 0


def _lab_node(bridge: Bridge) -> str:
    nodes = bridge.call("/rosapi/nodes").get("nodes", [])
    return nodes[0] if nodes else ""


def _drain(bridge: Bridge, seconds: float) -> None:
    """Wait, reading what the lab sends meanwhile (status lines: a refused publish is printed)."""
    end = time.monotonic() + seconds
    while True:
        left = end - time.monotonic()
        if left <= 0:
            return
        frame = bridge.receive(left)
        if frame is not None and frame.get("op") == "status" and frame.get("level") in ("error", "warning"):
            print(f"[WARN] the lab: {frame.get('msg')}", file=sys.stderr, flush=True)
