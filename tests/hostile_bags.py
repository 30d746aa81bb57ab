"""Hostile recordings made byte by byte (the MCAP and rosbag1 layouts from their specifications):
decompression bombs, chunks that lie about their size, records that claim more than the file has.
The tests of sim/recording/bounded.py and app/recording/bags.py, and the CLI's, refuse them."""

from __future__ import annotations

import bz2
import struct
from pathlib import Path

import lz4.frame
import zstandard

MAGIC = b"\x89MCAP0\r\n"
GIB = 1 << 30


def _string(text: str) -> bytes:
    raw = text.encode()
    return struct.pack("<I", len(raw)) + raw


def _record(opcode: int, body: bytes) -> bytes:
    return struct.pack("<BQ", opcode, len(body)) + body


def _header() -> bytes:
    return _record(0x01, _string("") + _string("hostile"))


def _schema_and_channel() -> bytes:
    schema = _record(0x03, struct.pack("<H", 1) + _string("std_msgs/String") + _string("jsonschema") + _string("{}"))
    channel = _record(0x04, struct.pack("<HH", 1, 1) + _string("/chatter") + _string("json") + struct.pack("<I", 0))
    return schema + channel


def _message_header(data_length: int) -> bytes:
    """A Message record's opcode, length and fields, before its data of `data_length` bytes."""
    return struct.pack("<BQ", 0x05, 22 + data_length) + struct.pack("<HIQQ", 1, 0, 0, 0)


def _chunk(stated: int, compression: str, data: bytes) -> bytes:
    body = struct.pack("<QQQI", 0, 0, stated, 0) + _string(compression) + struct.pack("<Q", len(data)) + data
    return _record(0x06, body)


def _end(summary: bytes = b"", summary_start: int = 0) -> bytes:
    return (
        _record(0x0F, struct.pack("<I", 0)) + summary + _record(0x02, struct.pack("<QQI", summary_start, 0, 0)) + MAGIC
    )


BLOCK = 16 << 20  # zero bytes compressed once; a bomb repeats the compressed block (cheap to make)


def zstd_zeros(prefix: bytes, zeros: int) -> bytes:
    """zstd frames of `prefix` then `zeros` zero bytes (a multiple of BLOCK), one frame a block."""
    compressor = zstandard.ZstdCompressor(level=3)
    return compressor.compress(prefix) + compressor.compress(bytes(BLOCK)) * (zeros // BLOCK)


def bomb(path: Path, message_bytes: int = 3 * GIB // 2, stated: int | None = None, summary: bool = False) -> Path:
    """One zstd chunk holding one message of `message_bytes` zero bytes (1.5 GB: a ~48 KB file);
    the chunk states `stated` bytes uncompressed (default: the truth). `summary`: a summary section
    whose chunk index states the size too."""
    inner = len(_message_header(0)) + message_bytes
    data = zstd_zeros(_message_header(message_bytes), message_bytes)
    start = MAGIC + _header() + _schema_and_channel()
    chunk = _chunk(inner if stated is None else stated, "zstd", data)
    tail = b""
    if summary:
        index = struct.pack("<QQQQ", 0, 0, len(start), len(chunk)) + struct.pack("<I", 0) + struct.pack("<Q", 0)
        index += _string("zstd") + struct.pack("<QQ", len(data), inner if stated is None else stated)
        tail = _record(0x08, index)
    body = start + chunk
    data_end = _record(0x0F, struct.pack("<I", 0))
    summary_start = len(body) + len(data_end) if summary else 0
    path.write_bytes(body + data_end + tail + _record(0x02, struct.pack("<QQI", summary_start, 0, 0)) + MAGIC)
    return path


def lz4_liar(path: Path, message_bytes: int = 256 << 20) -> Path:
    """An lz4 chunk that states 1 KiB uncompressed and holds a 256 MiB message (a frame a block)."""
    compressor = lz4.frame.LZ4FrameCompressor()
    parts = [compressor.begin(), compressor.compress(_message_header(message_bytes))]
    block = bytes(BLOCK)
    parts += [compressor.compress(block) for _ in range(message_bytes // BLOCK)]
    data = b"".join(parts) + compressor.flush()  # one frame, as a writer makes it
    path.write_bytes(MAGIC + _header() + _schema_and_channel() + _chunk(1024, "lz4", data) + _end())
    return path


def unknown_compression(path: Path) -> Path:
    path.write_bytes(MAGIC + _header() + _schema_and_channel() + _chunk(10, "brotli", b"0123456789") + _end())
    return path


def huge_record(path: Path) -> Path:
    """A message record outside any chunk claiming 100 GB (the file has a few bytes of it)."""
    path.write_bytes(MAGIC + _header() + _schema_and_channel() + struct.pack("<BQ", 0x05, 100 * GIB) + b"x" * 64)
    return path


def rosbag1_bomb(path: Path, stated: int | None = None, uncompressed: int = 3 * GIB // 2) -> Path:
    """A rosbag1 whose one bz2 chunk holds `uncompressed` zero bytes and states `stated` of them."""
    data = bz2.compress(bytes(BLOCK)) * (uncompressed // BLOCK)  # bz2 streams one after another

    def header(**fields: bytes) -> bytes:
        raw = b"".join(struct.pack("<I", len(k) + 1 + len(v)) + k.encode() + b"=" + v for k, v in fields.items())
        return struct.pack("<I", len(raw)) + raw

    bag_header = header(
        op=b"\x03", index_pos=struct.pack("<Q", 0), conn_count=struct.pack("<I", 0), chunk_count=struct.pack("<I", 1)
    )
    bag_header += struct.pack("<I", 4096 - len(bag_header) - 4 - 13) + b" " * (4096 - len(bag_header) - 4 - 13)
    chunk = header(op=b"\x05", compression=b"bz2", size=struct.pack("<I", uncompressed if stated is None else stated))
    chunk += struct.pack("<I", len(data)) + data
    path.write_bytes(b"#ROSBAG V2.0\n" + bag_header + chunk)
    return path


def rosbag1_with_definition(path: Path, msgtype: str, definition: str, data: bytes = b"") -> Path:
    """A rosbag1 of one message (`data`, its ROS 1 bytes) on /evil whose connection carries
    `definition` as its type's text, as the bag states it (rosbags' writer copies the text as given:
    nothing of it is checked)."""
    from rosbags.rosbag1 import Writer

    with Writer(path) as writer:
        connection = writer.add_connection("/evil", msgtype, msgdef=definition, md5sum="0" * 32)
        writer.write(connection, 1, data)
    return path


# a 4.9 KB-class bag: one fixed array of 100 million empty messages (rosbags builds every one)
FIXED_ARRAY = "evil/Empty[100000000] items\n" + "=" * 80 + "\nMSG: evil/Empty\n"
EMPTY_SEQUENCE = "evil/Empty[] items\n" + "=" * 80 + "\nMSG: evil/Empty\n"  # 4 bytes: 4 billion items
SELF_HOLDING = "evil/Loop[] next\nint32 value\n"  # a type that holds itself


def billion_laughs(folder: Path, levels: int = 9) -> Path:
    """A rosbag2 folder whose metadata.yaml's storage is 10^levels strings through YAML aliases (a
    few hundred bytes; expanded, gigabytes)."""
    folder.mkdir()
    lines = ['a0: &a0 "lol"'] + [f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 10)}]" for i in range(1, levels + 1)]
    lines += ["rosbag2_bagfile_information:", f"  storage_identifier: *a{levels}"]
    (folder / "metadata.yaml").write_text("\n".join(lines) + "\n")
    return folder


def sqlite_view(folder: Path) -> Path:
    """A rosbag2 SQLite folder whose `messages` is a recursive VIEW (a query of it never ends)."""
    import sqlite3

    folder.mkdir()
    (folder / "metadata.yaml").write_text("rosbag2_bagfile_information: {storage_identifier: sqlite3}\n")
    connection = sqlite3.connect(folder / "evil.db3")
    connection.executescript(
        """
        CREATE TABLE topics (id INTEGER PRIMARY KEY, name TEXT, type TEXT, serialization_format TEXT,
                             offered_qos_profiles TEXT);
        CREATE VIEW messages AS
            WITH RECURSIVE n(id, topic_id, timestamp, data) AS (
                SELECT 1, 1, 1, x'00' UNION ALL SELECT id + 1, 1, timestamp + 1, data FROM n
            )
            SELECT * FROM n;
        """
    )
    connection.close()
    return folder


# `python -c MEASURE hri-lab-arguments...`: the command run in this process, then its peak resident
# memory (maxrss, KiB) on stderr as `maxrss_kib N` (the tests' and bench/bags.py's memory bound)
MEASURE = """
import resource, sys
from app.cli.main import main
try:
    code = main(sys.argv[1:])
finally:
    print("maxrss_kib", resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, file=sys.stderr)
raise SystemExit(code)
"""
