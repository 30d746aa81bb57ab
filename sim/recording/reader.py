"""Reading recordings back (the `mcap` library): messages, metadata and `bag info`.

Every file is read front to back, in file order, within the stated memory bound of
sim/recording/bounded.py (a crafted file is refused with its reason, never decompressed beyond its
caps); a finished file's summary gives `bag info` without reading the messages. A file cut short
(its writer was killed) has no summary: it is read up to the last complete chunk, and `complete`
says so.
"""

from __future__ import annotations

import codecs
import json
import struct
from collections.abc import Iterator
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import NamedTuple

from mcap.exceptions import McapError
from mcap.records import Channel, Metadata, Schema
from mcap.records import Message as McapMessage

from sim.recording import bounded


class Message(NamedTuple):
    topic: str
    schema: str
    log_time: int  # ns
    data: dict | bytes  # bytes when read with decode=False


class RecordingError(Exception):
    """Not a readable recording (the reason is the message)."""


MCAP_MAGIC = b"\x89MCAP0\r\n"  # the first bytes of every MCAP file (the MCAP specification)
HOW_TO_RECORD = "make one with `hri-lab record`, `hri-lab experiment --record DIR` or the lab's /start_recording"


def check_file(path: Path) -> None:
    """Raise RecordingError saying what `path` is when it is not an MCAP file: missing, a folder,
    empty, text or some other binary (a file cut short after MCAP's magic bytes is still read)."""
    if path.is_dir():
        raise RecordingError(f"{path}: a folder, not an MCAP recording: name a .mcap file in it")
    if not path.is_file():
        raise RecordingError(f"{path}: no such file")
    with open(path, "rb") as f:
        head = f.read(4096)
    if head.startswith(MCAP_MAGIC):
        return
    if not head:
        what = "an empty file"
    elif len(head) < len(MCAP_MAGIC) and MCAP_MAGIC.startswith(head):
        what = "a file cut short before its first record"
    else:
        try:
            codecs.getincrementaldecoder("utf-8")().decode(head)  # a character cut at 4096 bytes is text too
            what = "a text file"
        except UnicodeDecodeError:
            what = "a binary file of another format"
    raise RecordingError(
        f"{path}: not an MCAP recording ({what}; an MCAP file starts with the bytes \\x89MCAP0): {HOW_TO_RECORD}"
    )


def summary(path: Path):
    """The file's MCAP summary, None for a file cut short (a hostile one: RecordingError)."""
    try:
        with open(path, "rb") as f:
            return bounded.summary(f)
    except bounded.HostileRecording as exc:
        raise RecordingError(f"{path}: {exc}") from None
    except OSError:
        if not path.exists():
            raise RecordingError(f"{path}: no such file") from None
        raise


def records(path: str | Path, topics: list[str] | None = None) -> Iterator[tuple[Channel, Schema | None, McapMessage]]:
    """Every message record with its channel and schema, in file order (bounded.py's caps); a
    file's broken tail is the end of a file cut short, an error in a finished file."""
    path = Path(path)
    check_file(path)
    complete = summary(path) is not None
    schemas: dict[int, Schema] = {}
    channels: dict[int, Channel] = {}
    wanted = set(topics) if topics is not None else None
    with open(path, "rb") as f:
        try:
            for record in bounded.records(f):
                if isinstance(record, Schema):
                    schemas[record.id] = record
                elif isinstance(record, Channel):
                    channels[record.id] = record
                elif isinstance(record, McapMessage):
                    channel = channels.get(record.channel_id)
                    if channel is None:
                        raise RecordingError(
                            f"{path}: a message on channel {record.channel_id}, which no record defines"
                        )
                    if wanted is None or channel.topic in wanted:
                        yield channel, schemas.get(channel.schema_id), record
        except bounded.HostileRecording as exc:
            raise RecordingError(f"{path}: {exc}") from None
        except (McapError, EOFError, ValueError, struct.error, UnicodeDecodeError) as exc:
            if complete:
                raise RecordingError(f"{path}: broken MCAP ({type(exc).__name__}: {str(exc)[:200]})") from None


def messages(path: str | Path, topics: list[str] | None = None, decode: bool = True) -> Iterator[Message]:
    """Every message in file order (the lab writes them in log-time order), decoded from JSON
    (decode=False: the raw bytes)."""
    for channel, schema, message in records(path, topics):
        try:
            data = json.loads(message.data) if decode else bytes(message.data)
        except ValueError:
            raise RecordingError(
                f"{path}: a message on {channel.topic[:100]} is not JSON (encoding {channel.message_encoding[:20]!r})"
            ) from None
        yield Message(channel.topic, schema.name if schema else "", message.log_time, data)


def metadata(path: str | Path) -> dict[str, dict]:
    """name -> record of the file's metadata (values decoded from JSON where they are JSON)."""
    path = Path(path)
    check_file(path)
    out: dict[str, dict] = {}
    indexed = summary(path)
    with open(path, "rb") as f:
        try:
            found = bounded.metadata(f, indexed) if indexed is not None else bounded.records(f)
            for record in found:
                if isinstance(record, Metadata):
                    out[record.name] = {k: _json_or_text(v) for k, v in record.metadata.items()}
        except bounded.HostileRecording as exc:
            raise RecordingError(f"{path}: {exc}") from None
        except (McapError, EOFError, ValueError, struct.error, UnicodeDecodeError):
            pass  # a file cut short: what was written so far
    return out


def _json_or_text(value: str):
    try:
        return json.loads(value)
    except ValueError:
        return value


@dataclass
class TopicInfo:
    name: str
    type: str
    count: int
    encoding: str = "json"


@dataclass
class BagInfo:
    path: Path
    size: int  # bytes
    complete: bool  # False: cut short (no index/summary); figures from what could be read
    start: int  # ns
    end: int  # ns
    messages: int
    topics: list[TopicInfo] = field(default_factory=list)
    storage: str = "mcap"  # what `ros2 bag info` calls the storage (rosbag1 for a ROS 1 .bag)

    @property
    def duration(self) -> float:
        """s"""
        return (self.end - self.start) / 1e9 if self.messages else 0.0

    def as_dict(self) -> dict:
        return {
            "path": str(self.path),
            "size": self.size,
            "complete": self.complete,
            "duration": self.duration,
            "start": self.start,
            "end": self.end,
            "messages": self.messages,
            "topics": [vars(t) for t in self.topics],
            "storage": self.storage,
        }


def info(path: str | Path) -> BagInfo:
    """What `ros2 bag info` tells: size, duration, start, end, message count, topics with type and count."""
    path = Path(path)
    check_file(path)
    found = summary(path)
    if found is not None and found.statistics is not None:
        stats = found.statistics
        topics = [
            TopicInfo(
                c.topic,
                found.schemas[c.schema_id].name if c.schema_id in found.schemas else "",
                stats.channel_message_counts.get(cid, 0),
                c.message_encoding,
            )
            for cid, c in sorted(found.channels.items())
        ]
        return BagInfo(
            path,
            path.stat().st_size,
            True,
            stats.message_start_time,
            stats.message_end_time,
            stats.message_count,
            topics,
        )
    counts: dict[str, TopicInfo] = {}
    start, end, total = None, None, 0
    for m in messages(path):
        counts.setdefault(m.topic, TopicInfo(m.topic, m.schema, 0)).count += 1
        start = m.log_time if start is None else min(start, m.log_time)
        end = m.log_time if end is None else max(end, m.log_time)
        total += 1
    return BagInfo(path, path.stat().st_size, False, start or 0, end or 0, total, list(counts.values()))


def _when(ns: int) -> str:
    t = datetime.fromtimestamp(ns / 1e9, tz=UTC)
    return f"{t:%b %d %Y %H:%M:%S}.{int(ns % 1_000_000_000) // 1_000_000:03d} ({ns / 1e9:.3f})"


def format_info(bag: BagInfo) -> str:
    """The layout of `ros2 bag info`."""
    size = bag.size
    human = f"{size / 2**20:.1f} MiB" if size >= 2**20 else f"{size / 2**10:.1f} KiB"
    lines = [
        f"Files:             {bag.path.name}",
        f"Bag size:          {human}",
        f"Storage id:        {bag.storage}"
        + ("" if bag.complete else "  (cut short: no index; read up to the last complete chunk)"),
        f"Duration:          {bag.duration:.3f}s",
        f"Start:             {_when(bag.start)}",
        f"End:               {_when(bag.end)}",
        f"Messages:          {bag.messages}",
    ]
    width = max((len(t.name) for t in bag.topics), default=0)
    type_width = max((len(t.type) for t in bag.topics), default=0)
    for i, t in enumerate(bag.topics):
        prefix = "Topic information: " if i == 0 else " " * 19
        lines.append(
            f"{prefix}Topic: {t.name:<{width}} | Type: {t.type:<{type_width}} | Count: {t.count} | "
            f"Serialization Format: {t.encoding}"
        )
    return "\n".join(lines)
