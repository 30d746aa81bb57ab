"""sim/recording/bounded.py: every hostile MCAP refused with its reason before it is decompressed
beyond its caps, and an honest file read whole (tests/hostile_bags.py makes the hostile ones)."""

import json

import pytest
import zstandard
from mcap.records import Chunk
from mcap.writer import CompressionType, Writer

from sim.recording import bounded, reader

from tests import hostile_bags


def _refusal(path) -> str:
    with pytest.raises(reader.RecordingError) as refused:
        list(reader.messages(path))
    return str(refused.value)


def test_a_bomb_is_refused_from_its_chunk_header_before_decompressing(tmp_path):
    path = hostile_bags.bomb(tmp_path / "bomb.mcap")
    assert path.stat().st_size < 100_000  # 1.5 GB of message in a ~50 KB file
    assert "a chunk states 1536.0 MiB uncompressed, over the cap of 64.0 MiB" in _refusal(path)


def test_a_bomb_is_refused_from_its_summary_first(tmp_path):
    path = hostile_bags.bomb(tmp_path / "bomb.mcap", summary=True)
    with pytest.raises(reader.RecordingError, match=r"its summary states a chunk of 1536.0 MiB"):
        reader.info(path)
    assert "its summary states a chunk of 1536.0 MiB" in _refusal(path)


def test_a_zstd_chunk_that_states_less_than_it_holds_is_refused(tmp_path):
    path = hostile_bags.bomb(tmp_path / "liar.mcap", message_bytes=bounded.MAX_CHUNK_BYTES * 2, stated=1000)
    assert "states 1000 bytes uncompressed but holds more" in _refusal(path)


def test_an_lz4_chunk_that_states_less_than_it_holds_is_refused(tmp_path):
    path = hostile_bags.lz4_liar(tmp_path / "liar.mcap")
    assert "states 1024 bytes uncompressed but holds more" in _refusal(path)


def test_a_compression_mcap_does_not_define_is_named(tmp_path):
    assert "compressed with 'brotli'" in _refusal(hostile_bags.unknown_compression(tmp_path / "x.mcap"))


def test_a_record_longer_than_the_cap_is_refused_before_it_is_read(tmp_path):
    assert "a record over the cap of 64.0 MiB" in _refusal(hostile_bags.huge_record(tmp_path / "x.mcap"))


def test_decompress_keeps_to_the_stated_size():
    data = b"abc" * 1000
    chunk = Chunk(
        compression="zstd",
        data=zstandard.compress(data),
        message_start_time=0,
        message_end_time=0,
        uncompressed_crc=0,
        uncompressed_size=len(data),
    )
    assert bounded.decompress(chunk) == data
    short = Chunk(
        compression="zstd",
        data=zstandard.compress(data),
        message_start_time=0,
        message_end_time=0,
        uncompressed_crc=0,
        uncompressed_size=len(data) + 5,
    )
    with pytest.raises(
        bounded.HostileRecording, match=f"states {len(data) + 5} bytes uncompressed but holds {len(data)}"
    ):
        bounded.decompress(short)


@pytest.mark.parametrize("compression", [CompressionType.ZSTD, CompressionType.LZ4, CompressionType.NONE])
def test_an_honest_recording_reads_whole_in_order(tmp_path, compression):
    path = tmp_path / "ok.mcap"
    with open(path, "wb") as f:
        writer = Writer(f, chunk_size=4096, compression=compression)
        writer.start(profile="", library="test")
        schema = writer.register_schema("std_msgs/Int32", "jsonschema", b"{}")
        channel = writer.register_channel("/count", "json", schema)
        for i in range(2000):
            writer.add_message(channel, i * 1_000_000, json.dumps({"data": i}).encode(), i * 1_000_000)
        writer.add_metadata("hri_lab", {"source": "test"})
        writer.finish()
    got = list(reader.messages(path))
    assert [m.data["data"] for m in got] == list(range(2000))
    assert reader.info(path).messages == 2000
    assert reader.metadata(path)["hri_lab"]["source"] == "test"
