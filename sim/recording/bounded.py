"""Reading MCAP records within a stated memory bound, whatever the file claims.

An MCAP file is untrusted input (a student's, a download): a 48 KB file can hold one zstd chunk
that decompresses to 1.5 GB. Every record is read here, front to back, with the `mcap` library's
StreamReader (chunks handed over still compressed) and:

- a record longer than MAX_RECORD_BYTES on disk is refused before it is read;
- a chunk is refused before it is decompressed when its stated uncompressed size is over
  MAX_CHUNK_BYTES or its compression is not one MCAP defines ("", zstd, lz4);
- a chunk is decompressed with its stated size as the output's bound (zstd's, lz4's streaming
  decompressors given `max_length`): a chunk whose data decompresses to more than it states is
  refused, never held (the `mcap` library's own reader trusts a zstd frame's header and decompresses
  lz4 with no bound at all).

So reading holds at most one chunk's records (MAX_CHUNK_BYTES, twice: the bytes and the records cut
from them) beside one compressed record: `bag info`, `bag play` and `hri-lab play` stay within
MEMORY_BOUND_BYTES of the process's own on any file (docs/recording.md, "Hostile files").
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import BinaryIO

import lz4.frame
import zstandard
from mcap.exceptions import McapError, RecordLengthLimitExceeded
from mcap.reader import FOOTER_SIZE
from mcap.records import Channel, Chunk, ChunkIndex, Footer, McapRecord, MetadataIndex, Schema, Statistics
from mcap.stream_reader import MAGIC_SIZE, StreamReader, breakup_chunk
from mcap.summary import Summary

MAX_CHUNK_BYTES = 64 << 20  # a chunk's decompressed size (the lab writes 256 KiB chunks; rosbag2 1 MiB)
MAX_RECORD_BYTES = 64 << 20  # one record as stored (an uncompressed message outside chunks too)
MEMORY_BOUND_BYTES = 3 * MAX_CHUNK_BYTES + MAX_RECORD_BYTES  # what reading may hold at once, stated
COMPRESSIONS = ("", "zstd", "lz4")


class HostileRecording(ValueError):
    """A record over a cap, or a chunk that is not what it says (the reason is the message)."""


def _mib(n: int) -> str:
    return f"{n / 2**20:.1f} MiB"


def decompress(chunk: Chunk, cap: int = MAX_CHUNK_BYTES) -> bytes:
    """The chunk's records as bytes, never more than min(stated size, cap) of them."""
    stated = chunk.uncompressed_size
    if chunk.compression not in COMPRESSIONS:
        raise HostileRecording(f"a chunk compressed with {chunk.compression[:20]!r} (MCAP defines zstd and lz4)")
    if stated > cap:
        raise HostileRecording(
            f"a chunk states {_mib(stated)} uncompressed, over the cap of {_mib(cap)}: refused before decompressing"
        )
    data = bytes(chunk.data)
    if chunk.compression == "":
        out = data
    elif chunk.compression == "zstd":
        reader = zstandard.ZstdDecompressor().stream_reader(data, read_across_frames=True)
        try:
            out = reader.read(stated + 1)
        except zstandard.ZstdError as exc:
            raise HostileRecording(f"a zstd chunk does not decompress: {exc}") from None
    else:
        decompressor = lz4.frame.LZ4FrameDecompressor()
        try:
            out = decompressor.decompress(data, max_length=stated + 1)
        except RuntimeError as exc:
            raise HostileRecording(f"an lz4 chunk does not decompress: {exc}") from None
    if len(out) != stated:
        raise HostileRecording(
            f"a chunk states {stated} bytes uncompressed but holds {'more' if len(out) > stated else len(out)}: refused"
        )
    return out


def records(f: BinaryIO, chunk_cap: int = MAX_CHUNK_BYTES) -> Iterator[McapRecord]:
    """Every record of the file in file order, a chunk's records in its place (each under the caps).
    Raises HostileRecording for a record or chunk over a cap, McapError/EOFError where the file ends
    or breaks (a file cut short: what came before was yielded)."""
    stream = StreamReader(f, emit_chunks=True, record_size_limit=MAX_RECORD_BYTES)
    try:
        for record in stream.records:
            if isinstance(record, Chunk):
                plain = Chunk(
                    compression="",
                    data=decompress(record, chunk_cap),
                    message_start_time=record.message_start_time,
                    message_end_time=record.message_end_time,
                    uncompressed_crc=0,
                    uncompressed_size=record.uncompressed_size,
                )
                yield from breakup_chunk(plain)
            else:
                yield record
    except RecordLengthLimitExceeded as exc:
        raise HostileRecording(f"a record over the cap of {_mib(MAX_RECORD_BYTES)}: refused ({exc})") from None


def summary(f: BinaryIO, chunk_cap: int = MAX_CHUNK_BYTES) -> Summary | None:
    """The file's summary section (None when it has none: a file cut short), read from the footer
    with the record cap; its chunk indexes' stated sizes are checked against the chunk cap, so a
    bomb is refused from the summary before anything is decompressed."""
    try:
        f.seek(-(FOOTER_SIZE + MAGIC_SIZE), 2)
        footer = next(StreamReader(f, skip_magic=True, record_size_limit=MAX_RECORD_BYTES).records)
    except (McapError, EOFError, OSError, StopIteration, ValueError):
        return None
    if not isinstance(footer, Footer) or footer.summary_start == 0:
        return None
    out = Summary()
    f.seek(footer.summary_start)
    try:
        for record in StreamReader(f, skip_magic=True, emit_chunks=True, record_size_limit=MAX_RECORD_BYTES).records:
            if isinstance(record, Footer):
                break
            if isinstance(record, Chunk):
                raise HostileRecording("a chunk inside the summary section: not an MCAP file's layout")
            if isinstance(record, Statistics):
                out.statistics = record
            elif isinstance(record, Schema):
                out.schemas[record.id] = record
            elif isinstance(record, Channel):
                out.channels[record.id] = record
            elif isinstance(record, ChunkIndex):
                if record.uncompressed_size > chunk_cap:
                    raise HostileRecording(
                        f"its summary states a chunk of {_mib(record.uncompressed_size)} uncompressed, over the "
                        f"cap of {_mib(chunk_cap)}: refused before decompressing"
                    )
                out.chunk_indexes.append(record)
            elif isinstance(record, MetadataIndex):
                out.metadata_indexes.append(record)
    except RecordLengthLimitExceeded as exc:
        raise HostileRecording(f"a summary record over the cap of {_mib(MAX_RECORD_BYTES)}: refused ({exc})") from None
    except (McapError, EOFError) as exc:
        raise HostileRecording(f"its summary section is broken: {str(exc)[:200]}") from None
    return out


def metadata(f: BinaryIO, found: Summary) -> Iterator[McapRecord]:
    """The metadata records a summary indexes, each read at its offset (nothing decompressed)."""
    for index in found.metadata_indexes:
        if index.length > MAX_RECORD_BYTES:
            raise HostileRecording(
                f"a metadata record of {_mib(index.length)}, over the cap of {_mib(MAX_RECORD_BYTES)}"
            )
        f.seek(index.offset)
        yield next(StreamReader(f, skip_magic=True, record_size_limit=MAX_RECORD_BYTES).records)
