"""Every client's streams share the lab's outgoing rate (app/rosbridge/bridge.py,
MAX_OUTGOING_RATE; app/rosbridge/internal/streams.py): a stream's period is at least its share,
in powers of two of milliseconds, and a stream that stops gives its share back."""

import asyncio
from types import SimpleNamespace

from app.rosbridge.bridge import MAX_OUTGOING_RATE, Bridge
from app.rosbridge.internal.streams import Stream


def test_streams_share_the_labs_outgoing_rate():
    async def run() -> None:
        bridge = SimpleNamespace(streams=0)
        bridge.fair_period = lambda: Bridge.fair_period(bridge)  # type: ignore[arg-type]
        session = SimpleNamespace(bridge=bridge)
        streams = []
        for _ in range(80):
            stream = Stream(session, "/joint_states")
            stream.options["id"] = (0, 0)  # throttle_rate 0: as fast as it may
            streams.append(stream)
        assert bridge.streams == 80
        assert streams[0].period == 0.016  # 80 / 5000 messages/s = 16 ms
        assert len(streams) / streams[0].period <= MAX_OUTGOING_RATE
        for stream in streams[5:]:
            stream.stop()
            stream.stop()  # twice: counted once
        assert bridge.streams == 5
        assert streams[0].period == 0.001

    asyncio.run(run())
