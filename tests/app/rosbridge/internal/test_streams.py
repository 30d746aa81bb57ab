"""Every client's streams share the lab's outgoing rate (app/rosbridge/managers/topics.py,
MAX_OUTGOING_RATE; app/rosbridge/internal/streams.py): a stream's period is at least its share,
in powers of two of milliseconds, and a stream that stops gives its share back."""

import asyncio
from types import SimpleNamespace

from app.lab.world import LIFTING
from app.rosbridge.internal.streams import Stream
from app.rosbridge.managers.topics import MAX_OUTGOING_RATE, TopicManager


def test_streams_share_the_labs_outgoing_rate():
    async def run() -> None:
        topics = TopicManager(LIFTING, replay=True)
        session = SimpleNamespace(bridge=SimpleNamespace(topics=topics))
        streams = []
        for _ in range(80):
            stream = Stream(session, "/joint_states")
            stream.options["id"] = (0, 0)  # throttle_rate 0: as fast as it may
            streams.append(stream)
        assert topics.streams == 80
        assert streams[0].period == 0.016  # 80 / 5000 messages/s = 16 ms
        assert len(streams) / streams[0].period <= MAX_OUTGOING_RATE
        for stream in streams[5:]:
            stream.stop()
            stream.stop()  # twice: counted once
        assert topics.streams == 5
        assert streams[0].period == 0.001

    asyncio.run(run())
