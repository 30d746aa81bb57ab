"""What the streams of one topic share, however many clients subscribe: a lab topic's message built
once per sample (per topic and simulation time) and a message's publish frame encoded once (per
message object). Twenty clients at throttle_rate 0 then cost the event loop one build and one
encoding of each message, and twenty sends, not twenty of each (issue 33: HTTP kept responsive)."""

from __future__ import annotations

import json
from collections import OrderedDict
from collections.abc import Callable

from sim.messages import Base64Text

KEEP_BUILT = 64  # messages kept per topic by simulation time: streams a few samples apart still share
KEEP_FRAMES = 8  # encoded frames kept per topic (an image's is a few MB)


class SharedMessages:
    def __init__(self) -> None:
        self._built: dict[str, OrderedDict[float, dict]] = {}
        self._frames: dict[str, OrderedDict[tuple[int, int], tuple[dict, str]]] = {}

    def built(self, topic: str, time_s: float, make: Callable[[], dict]) -> dict:
        """The topic's message at `time_s`: made once, the same object for every stream."""
        kept = self._built.setdefault(topic, OrderedDict())
        message = kept.get(time_s)
        if message is None:
            message = kept[time_s] = make()
            if len(kept) > KEEP_BUILT:
                kept.popitem(last=False)
        return message

    def frame(self, topic: str, message: dict, header: dict | None = None) -> str:
        """rosbridge's publish frame of `message` on `topic`, as text: encoded once per message (and
        once more with `connection_header`, the publisher's header, for the streams that asked)."""
        kept = self._frames.setdefault(topic, OrderedDict())
        key = (id(message), header is not None)
        found = kept.get(key)
        if found is not None and found[0] is message:  # the object itself (kept alive here): not a reused id
            return found[1]
        frame: dict = {"op": "publish", "topic": topic, "msg": message}
        if header is not None:
            frame["connection_header"] = header
        text = dumps(frame)
        kept[key] = (message, text)
        if len(kept) > KEEP_FRAMES:
            kept.popitem(last=False)
        return text

    def forget(self, topic: str) -> None:
        """Nobody subscribes to `topic` any more: its messages go."""
        self._built.pop(topic, None)
        self._frames.pop(topic, None)


def dumps(frame: dict) -> str:
    """json.dumps of a frame, its message's Base64Text values (an image's data: no character needs
    an escape) put in as they are instead of scanned by json's encoder, which held the event loop
    5.6 ms per 640x480 image (30 a second) where this takes a fraction of a millisecond."""
    msg = frame.get("msg")
    if not isinstance(msg, dict):
        return json.dumps(frame)
    verbatim = {k: v for k, v in msg.items() if isinstance(v, Base64Text)}
    if not verbatim:
        return json.dumps(frame)
    holders = {k: f"\x00{k}" for k in verbatim}  # the lab's own message: no other value of it is this text
    text = json.dumps({**frame, "msg": {**msg, **holders}})
    for k, value in verbatim.items():
        text = text.replace(json.dumps(holders[k]), f'"{value}"', 1)
    return text
