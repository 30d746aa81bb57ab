"""Bags a real ROS opens and reads: rosbag2 (MCAP storage, `ros2msg` schemas, CDR, metadata.yaml)
written, rosbag1 `.bag` converted to, and any of them (and the lab's own JSON MCAP) read back as
rosbridge's JSON — all with the `rosbags` library (its type store parses the definitions and does
the CDR and ROS 1 serialization; nothing here serializes by hand).

- `BagWriter` writes a rosbag2 folder (`NAME/NAME.mcap` + `metadata.yaml`) from rosbridge JSON
  messages and each topic's definition text (a program's own type carries its definition);
- `open_bag` reads a rosbag1 `.bag`, a rosbag2 folder (MCAP or SQLite), a bare rosbag2 `.mcap` and
  the lab's JSON MCAP: `info()` and `messages()` (time order for rosbag1/SQLite, file order for
  MCAP, which writers keep in time order) as JSON a rosbridge client publishes;
- `to_rosbag1` converts any of them to a ROS 1 `.bag`.

Untrusted files: an MCAP is read through sim/recording/bounded.py (every chunk within its cap);
a rosbag1's chunks are checked the same way before `rosbags` decompresses them (`check_rosbag1`);
a rosbag2 SQLite's tables (plain tables: no view, virtual table or generated column), then its
largest message and compression are checked before it is read; a metadata.yaml is read without
YAML aliases; every definition a bag carries is held to the lab's caps (interfaces/definition_limits.py:
a fixed array's length, a default's values, the fields, no recursive type: `check_types`).
"""

from __future__ import annotations

import bz2
import dataclasses
import re
import sqlite3
import struct
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import lz4.frame
import numpy as np
import pybase64
import yaml
from rosbags.interfaces import Nodetype
from rosbags.rosbag1 import Reader as Rosbag1Reader
from rosbags.rosbag1 import Writer as Rosbag1Writer
from rosbags.rosbag2 import Reader as Rosbag2Reader
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Rosbag2Writer
from rosbags.typesys import Stores, get_types_from_msg, get_typestore
from rosbags.typesys.store import Typestore

from sim.recording import bounded, reader
from sim.recording.reader import BagInfo, RecordingError, TopicInfo

from interfaces.definition_limits import (
    MAX_DEFAULT_VALUES,
    MAX_DEFINITION_CHARS,
    MAX_DEFINITION_FIELDS,
    MAX_FIXED_ARRAY,
)

MAX_MESSAGE_BYTES = bounded.MAX_CHUNK_BYTES  # one message of any bag (a 640x480 rgb8 image is 0.9 MiB)
ROS1_MAGIC = b"#ROSBAG V2.0\n"
_TYPE = re.compile(r"^([A-Za-z]\w*)/(?:(msg)/)?([A-Za-z]\w*)$")


@dataclass
class BagMessage:
    topic: str
    type: str  # pkg/msg/Name
    log_time: int  # ns
    data: dict  # rosbridge's JSON


def ros2_type(name: str) -> str:
    """'pkg/Name' or 'pkg/msg/Name' -> 'pkg/msg/Name' (rosbag2's and rosbags' form)."""
    match = _TYPE.match(name.strip("/"))
    if match is None:
        raise RecordingError(f"not a message type name: {name[:100]!r} (expected PACKAGE/Name)")
    return f"{match[1]}/msg/{match[3]}"


def ros1_type(name: str) -> str:
    """'pkg/msg/Name' -> 'pkg/Name' (what rosbridge and ROS 1 call it)."""
    package, *_, message = name.split("/")
    return f"{package}/{message}"


def typestore(definitions: dict[str, str] | None = None, ros1: bool = False) -> Typestore:
    """ROS 2's standard types (Humble; ROS 1's, Noetic, with `ros1`) and the given ones (type ->
    full definition text, ROS 1's concatenated form `====...` / `MSG: pkg/Name` for nested types)."""
    store = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    for name, text in (definitions or {}).items():
        register(store, name, text)
    return store


def register(store: Typestore, name: str, text: str) -> None:
    """Add a type (and the nested types it brings that the store lacks: a standard type the store
    has keeps its own definition, e.g. ROS 1's Header with its seq in a ROS 1 store) from its
    definition text; a definition that does not parse is refused by name."""
    if len(text) > MAX_DEFINITION_CHARS:
        raise RecordingError(f"the definition of {name[:100]}: {len(text)} characters, at most {MAX_DEFINITION_CHARS}")
    try:
        found = get_types_from_msg(text, ros2_type(name))
        new = {k: v for k, v in found.items() if k not in store.fielddefs}
        check_types(name, new, store)
        store.register(new)
    except RecordingError:
        raise
    except (Exception, RecursionError) as exc:  # noqa: BLE001 - rosbags' parser errors have several types
        raise RecordingError(f"the definition of {name[:100]} does not parse: {str(exc)[:200]}") from None


def check_types(name: str, found: dict[str, Any], store: Typestore) -> None:
    """The lab's definition caps (interfaces/definition_limits.py) on the types a bag's text brings, before
    the store makes classes of them: a fixed array's length, the values a message's default holds
    (nested messages and fixed arrays counted: rosbags builds them whole), the fields, no type that
    holds itself (ROS refuses one; rosbags' hash of it recurses forever) and no variable-length array
    of a message of no bytes (four bytes of length would make billions). RecordingError names it."""
    fields = sum(len(fielddefs[1]) for fielddefs in found.values())
    if fields > MAX_DEFINITION_FIELDS:
        raise RecordingError(
            f"the definition of {name[:100]}: {fields} fields, over the cap of {MAX_DEFINITION_FIELDS}"
        )
    check = _TypeCheck(f"the definition of {name[:100]}", found, store)
    for msgtype in found:
        check.held(msgtype)


class _TypeCheck:
    """check_types' walk: each type's default values counted once (as interfaces/packages.py
    counts them), the types being counted kept to find a loop."""

    def __init__(self, where: str, found: dict[str, Any], store: Typestore) -> None:
        self.where, self.found, self.store = where, found, store
        self.values: dict[str, int] = {}  # type -> the values its default holds
        self.making: list[str] = []

    def fielddefs(self, msgtype: str) -> Any:
        fielddefs = self.found.get(msgtype) or self.store.fielddefs.get(msgtype)
        if fielddefs is None:
            raise RecordingError(f"{self.where}: type {msgtype} is not defined")
        return fielddefs

    def held(self, msgtype: str) -> int:
        if msgtype in self.values:
            return self.values[msgtype]
        if msgtype in self.making:
            loop = " -> ".join([*self.making[self.making.index(msgtype) :], msgtype])
            raise RecordingError(f"{self.where}: type {msgtype} holds itself ({loop}): a recursive type")
        self.making.append(msgtype)
        total = 0
        for field_name, (kind, desc) in self.fielddefs(msgtype)[1]:
            total += self.count(kind, desc)
            if total > MAX_DEFAULT_VALUES:
                raise RecordingError(
                    f"{self.where}: the default of {msgtype} would hold more than {MAX_DEFAULT_VALUES} values "
                    f"(field '{field_name}')"
                )
        self.making.pop()
        self.values[msgtype] = max(total, 1)  # an empty message is an object all the same
        return self.values[msgtype]

    def count(self, kind: Nodetype, desc: Any) -> int:
        """The values a field's default holds."""
        if kind == Nodetype.BASE:
            return 1
        if kind == Nodetype.NAME:
            return self.held(desc)
        (inner_kind, inner_desc), length = desc
        if kind == Nodetype.SEQUENCE:
            self.count(inner_kind, inner_desc)  # its type checked; its default is empty
            if inner_kind == Nodetype.NAME and not self.takes_bytes(inner_desc):
                raise RecordingError(
                    f"{self.where}: a variable-length array of {inner_desc}, a message of no bytes: four bytes of "
                    "its length would make billions of them (refused)"
                )
            return 0
        if length > MAX_FIXED_ARRAY:
            raise RecordingError(
                f"{self.where}: a fixed-size array of {length} items, over the cap of {MAX_FIXED_ARRAY}"
            )
        return length * self.count(inner_kind, inner_desc)

    def takes_bytes(self, msgtype: str) -> bool:
        """Whether a message of `msgtype` takes any bytes serialized (its type checked acyclic first)."""
        for _, (kind, desc) in self.fielddefs(msgtype)[1]:
            if kind in (Nodetype.BASE, Nodetype.SEQUENCE) or (kind == Nodetype.NAME and self.takes_bytes(desc)):
                return True
            if kind == Nodetype.ARRAY and desc[1] > 0:
                inner_kind, inner_desc = desc[0]
                if inner_kind != Nodetype.NAME or self.takes_bytes(inner_desc):
                    return True
        return False


# --- JSON <-> rosbags' messages -----------------------------------------------------------------
_BYTES = ("uint8", "byte", "char", "int8")
_NUMPY = {
    "bool": np.bool_,
    "byte": np.uint8,
    "char": np.uint8,
    "int8": np.int8,
    "uint8": np.uint8,
    "int16": np.int16,
    "uint16": np.uint16,
    "int32": np.int32,
    "uint32": np.uint32,
    "int64": np.int64,
    "uint64": np.uint64,
    "float32": np.float32,
    "float64": np.float64,
}
_STAMP_ALIASES = {"secs": "sec", "nsecs": "nanosec"}  # ROS 1's names of a Time's fields


def from_json(store: Typestore, msgtype: str, data: Any, where: str = "msg") -> Any:
    """A rosbags message of `msgtype` from rosbridge's JSON (missing fields get ROS's defaults;
    arrays of bytes may be base64 text, as rosbridge sends them)."""
    if not isinstance(data, dict):
        raise RecordingError(f"{where}: expected an object for {msgtype}, got {type(data).__name__}")
    data = {_STAMP_ALIASES.get(k, k): v for k, v in data.items()}
    _, fields = store.fielddefs[msgtype][:2]
    values = {}
    for name, (kind, desc) in fields:
        value = data.get(name, data.get(name.lower(), data.get(name.upper())))  # CameraInfo's D (ROS 1), d (ROS 2)
        values[name] = _value(store, kind, desc, value, f"{where}.{name}")
    return store.types[msgtype](**values)


def _value(store: Typestore, kind: Nodetype, desc: Any, value: Any, where: str) -> Any:
    if kind == Nodetype.NAME:
        return from_json(store, desc, value if value is not None else {}, where)
    if kind == Nodetype.BASE:
        base = desc[0]
        if value is None:
            return "" if base in ("string", "wstring") else (False if base == "bool" else 0)
        if base in ("string", "wstring"):
            return str(value)
        if base == "bool":
            return bool(value)
        if base in ("float32", "float64"):
            return float(value)
        return int(value)
    inner, count = desc
    inner_kind, inner_desc = inner
    if inner_kind == Nodetype.BASE and inner_desc[0] in _NUMPY:
        dtype = _NUMPY[inner_desc[0]]
        array: np.ndarray
        if isinstance(value, str) and inner_desc[0] in _BYTES:
            array = np.frombuffer(pybase64.b64decode(value), dtype=dtype).copy()
        else:
            array = np.array(value if value is not None else [], dtype=dtype)
        if kind == Nodetype.ARRAY and len(array) != count:
            array = np.resize(array, count) if len(array) == 0 else array
            if len(array) != count:
                raise RecordingError(f"{where}: expected {count} items, got {len(array)}")
        return array
    items = list(value or [])
    return [_value(store, inner_kind, inner_desc, v, f"{where}[{i}]") for i, v in enumerate(items)]


def to_json(message: Any) -> Any:
    """rosbridge's JSON of a rosbags message: arrays of bytes as base64 text, numbers as JSON's."""
    if dataclasses.is_dataclass(message) and not isinstance(message, type):
        return {
            f.name: to_json(getattr(message, f.name))
            for f in dataclasses.fields(message)
            if not f.name.startswith("__")
        }
    if isinstance(message, np.ndarray):
        if message.dtype in (np.uint8, np.int8):
            return pybase64.b64encode(message.tobytes()).decode("ascii")
        return message.tolist()
    if isinstance(message, (list, tuple)):
        return [to_json(m) for m in message]
    if isinstance(message, np.generic):
        return message.item()
    return message


# --- writing rosbag2 ----------------------------------------------------------------------------
class BagWriter:
    """A rosbag2 folder (MCAP storage, CDR) being written from rosbridge JSON; `max_bytes` caps
    the messages' bytes (`write` returns False and `stopped` says why)."""

    def __init__(self, path: str | Path, max_bytes: int) -> None:
        self.path = Path(path)
        if self.path.exists():
            raise RecordingError(f"{self.path} exists: choose another name with -O")
        self.store = typestore()
        self.max_bytes = max_bytes
        self.bytes = 0
        self.stopped: str | None = None
        self.counts: dict[str, int] = {}
        self._connections: dict[str, Any] = {}
        self._types: dict[str, str] = {}
        self._writer = Rosbag2Writer(self.path, version=9, storage_plugin=StoragePlugin.MCAP)
        self._writer.open()

    def add_topic(self, topic: str, type_name: str, definition: str | None) -> None:
        """A topic and its type; `definition`, the full text, for a type ROS 2 does not ship."""
        msgtype = ros2_type(type_name)
        if msgtype not in self.store.fielddefs:
            if not definition:
                raise RecordingError(
                    f"{topic}: no definition of {type_name} (the program that publishes it carries it)"
                )
            register(self.store, msgtype, definition)
        try:  # its type's hash (RIHS01) and definition for the bag's metadata
            self._connections[topic] = self._writer.add_connection(topic, msgtype, typestore=self.store)
        except (Exception, RecursionError) as exc:  # noqa: BLE001 - rosbags' errors have several types
            raise RecordingError(f"{topic}: type {type_name} cannot be hashed for the bag: {str(exc)[:200]}") from None
        self._types[topic] = msgtype
        self.counts[topic] = 0

    def has(self, topic: str) -> bool:
        return topic in self._connections

    def write(self, topic: str, log_time: int, data: dict) -> bool:
        if self.stopped:
            return False
        msgtype = self._types[topic]
        raw = self.store.serialize_cdr(from_json(self.store, msgtype, data, topic), msgtype)
        if self.bytes + len(raw) > self.max_bytes:
            self.stopped = f"recording stopped: the messages reached the cap of {self.max_bytes / 2**20:.0f} MiB"
            return False
        self._writer.write(self._connections[topic], log_time, raw)
        self.bytes += len(raw)
        self.counts[topic] += 1
        return True

    def close(self) -> None:
        self._writer.close()


# --- reading any bag ----------------------------------------------------------------------------
@dataclass
class Bag:
    """A bag opened for reading: its kind, topics (type, definition) and messages as JSON."""

    path: Path
    kind: str  # rosbag1 | rosbag2-mcap | rosbag2-sqlite3 | hri-lab
    store: Typestore
    types: dict[str, str] = field(default_factory=dict)  # topic -> pkg/msg/Name
    definitions: dict[str, str] = field(default_factory=dict)  # pkg/msg/Name -> its text, when the bag carried it
    _info: BagInfo | None = None

    def info(self) -> BagInfo:
        assert self._info is not None
        return self._info

    def messages(self, topics: list[str] | None = None) -> Iterator[BagMessage]:
        wanted = set(topics) if topics is not None else None
        if self.kind == "hri-lab":
            for m in reader.messages(self.path, topics):
                if isinstance(m.data, dict):
                    yield BagMessage(m.topic, self.types.get(m.topic, m.schema), m.log_time, m.data)
        elif self.kind == "rosbag2-mcap":
            for channel, _, record in reader.records(_mcap_file(self.path), topics):
                msgtype = self.types[channel.topic]
                yield BagMessage(channel.topic, msgtype, record.log_time, self._decode_cdr(record.data, msgtype))
        else:
            yield from self._rosbags_messages(wanted)

    def _rosbags_messages(self, wanted: set[str] | None) -> Iterator[BagMessage]:
        """A rosbag1 (its chunks checked when it was opened) or a rosbag2 SQLite, through rosbags."""
        opened = Rosbag1Reader(self.path) if self.kind == "rosbag1" else Rosbag2Reader(self.path)
        try:
            with opened as bag:
                connections = [c for c in bag.connections if wanted is None or c.topic in wanted]
                for connection, log_time, raw in bag.messages(connections=connections):
                    msgtype = self.types[connection.topic]
                    if self.kind == "rosbag1":
                        data = to_json(self.store.deserialize_ros1(raw, msgtype))
                    else:
                        data = self._decode_cdr(raw, msgtype)
                    yield BagMessage(connection.topic, msgtype, log_time, data)
        except RecordingError:
            raise
        except Exception as exc:  # noqa: BLE001 - rosbags' reader and deserializers: a broken bag
            raise RecordingError(
                f"{self.path}: a message cannot be read ({type(exc).__name__}: {str(exc)[:200]})"
            ) from None

    def _decode_cdr(self, raw: bytes, msgtype: str) -> dict:
        try:
            return to_json(self.store.deserialize_cdr(raw, msgtype))
        except Exception as exc:  # noqa: BLE001 - a message that is not its type's CDR
            raise RecordingError(f"{self.path}: a {msgtype} message does not decode: {str(exc)[:200]}") from None


def _mcap_file(path: Path) -> Path:
    if path.is_dir():
        found = sorted(path.glob("*.mcap"))
        if not found:
            raise RecordingError(f"{path}: a folder with no .mcap file")
        return found[0]
    return path


def _is_rosbag2_mcap(path: Path) -> bool:
    """An MCAP whose channels are CDR (a rosbag2's), not the lab's JSON."""
    found = reader.summary(path)
    if found is not None:
        return any(c.message_encoding == "cdr" for c in found.channels.values())
    for channel, _, _ in reader.records(path):
        return channel.message_encoding == "cdr"
    return False


def open_bag(path: str | Path) -> Bag:
    """Open any bag for reading (refused with the reason: RecordingError)."""
    path = Path(path)
    if not path.exists():
        raise RecordingError(f"{path}: no such file or folder")
    if path.is_dir():
        meta = path / "metadata.yaml"
        if not meta.is_file():
            raise RecordingError(f"{path}: a folder, not an MCAP recording or a rosbag2 (no metadata.yaml in it)")
        storage = _rosbag2_storage(meta)
        if storage == "mcap":
            return _open_mcap(path, "rosbag2-mcap")
        return _open_sqlite(path)
    with open(path, "rb") as f:
        head = f.read(len(ROS1_MAGIC))
    if head == ROS1_MAGIC:
        return _open_rosbag1(path)
    if path.suffix == ".db3":
        raise RecordingError(f"{path}: a rosbag2 SQLite file: open its folder (with metadata.yaml)")
    reader.check_file(path)
    return _open_mcap(path, "rosbag2-mcap" if _is_rosbag2_mcap(path) else "hri-lab")


MAX_METADATA_BYTES = 1 << 20  # a rosbag2's metadata.yaml (ROS 2 writes a few KiB)
SQLITE_TABLES = ("messages", "topics")  # a rosbag2 SQLite's tables rosbags needs; `schema` and
SQLITE_OPTIONAL = ("schema", "message_definitions", "metadata")  # these it reads when they exist


def _metadata(meta: Path) -> Any:
    """metadata.yaml as data: at most MAX_METADATA_BYTES, and no YAML alias (`*name`: a few bytes of
    aliases expand to gigabytes, a "billion laughs") — refused from the events, before any is expanded."""
    with open(meta, "rb") as handle:
        raw = handle.read(MAX_METADATA_BYTES + 1)
    if len(raw) > MAX_METADATA_BYTES:
        raise RecordingError(f"{meta}: over {MAX_METADATA_BYTES >> 10} KiB: not a rosbag2 metadata.yaml")
    text = raw.decode("utf-8")
    for event in yaml.parse(text, Loader=yaml.SafeLoader):
        if isinstance(event, yaml.AliasEvent):
            raise RecordingError(f"{meta}: YAML aliases (*{str(event.anchor)[:40]}) are not read in a metadata.yaml")
    return yaml.safe_load(text)


def _rosbag2_storage(meta: Path) -> str:
    try:
        data = _metadata(meta)["rosbag2_bagfile_information"]
        storage = str(data["storage_identifier"])
        compression = str(data.get("compression_mode") or "")
    except RecordingError:
        raise
    except Exception as exc:  # noqa: BLE001 - any malformed metadata.yaml
        raise RecordingError(f"{meta}: not a rosbag2 metadata.yaml ({type(exc).__name__}: {str(exc)[:100]})") from None
    if compression and compression.upper() != "NONE":
        raise RecordingError(
            f"{meta}: compression mode {compression[:20]} is not read here (its decompressed size is not stated): "
            "decompress it with `ros2 bag convert` first"
        )
    if storage not in ("mcap", "sqlite3"):
        raise RecordingError(f"{meta}: storage {storage[:20]!r} (mcap and sqlite3 are read)")
    return storage


def _open_mcap(path: Path, kind: str) -> Bag:
    file = _mcap_file(path)
    summary_info = reader.info(file)
    store = typestore()
    types: dict[str, str] = {}
    definitions: dict[str, str] = {}
    if kind == "rosbag2-mcap":
        seen: set[int] = set()
        for channel, schema, _ in _channels(file):
            if channel.id in seen:
                continue
            seen.add(channel.id)
            if schema is None or schema.encoding not in ("ros2msg", "ros1msg"):
                raise RecordingError(
                    f"{file}: topic {channel.topic[:100]} has no ros2msg schema (encoding "
                    f"{schema.encoding[:20] if schema else 'none'!r})"
                )
            msgtype = ros2_type(schema.name)
            definitions[msgtype] = schema.data.decode("utf-8", errors="replace")
            if msgtype not in store.fielddefs:
                register(store, msgtype, definitions[msgtype])
            types[channel.topic] = msgtype
    else:  # the lab's JSON: its ROS types by name (the foxglove scene types are kept as they are)
        for t in summary_info.topics:
            types[t.name] = ros2_type(t.type) if _TYPE.match(t.type) else t.type
    summary_info.path = path
    return Bag(path, kind, store, types, definitions, summary_info)


def _channels(file: Path) -> Iterator[tuple[Any, Any, Any]]:
    """(channel, schema, None) of every channel: from the summary, else from the records."""
    found = reader.summary(file)
    if found is not None:
        for channel in found.channels.values():
            yield channel, found.schemas.get(channel.schema_id), None
        return
    yield from reader.records(file)


def _connections(store: Typestore, connections: list[Any]) -> tuple[dict[str, str], dict[str, str]]:
    """topic -> type and type -> definition text of rosbags' connections, each type the store lacks
    registered from the text the bag carries."""
    types, definitions = {}, {}
    for c in connections:
        msgtype = ros2_type(c.msgtype)
        text = c.msgdef.data if c.msgdef else ""
        if text:
            definitions[msgtype] = text
            if msgtype not in store.fielddefs:
                register(store, msgtype, text)
        types[c.topic] = msgtype
    return types, definitions


def _open_rosbag1(path: Path) -> Bag:
    check_rosbag1(path)
    store = typestore(ros1=True)
    try:
        with Rosbag1Reader(path) as bag:
            types, definitions = _connections(store, bag.connections)
            topics = [
                TopicInfo(name, ros1_type(types[name]), info.msgcount, "ros1") for name, info in bag.topics.items()
            ]
            count = bag.message_count
            info = BagInfo(
                path,
                path.stat().st_size,
                True,
                bag.start_time if count else 0,
                bag.end_time if count else 0,
                count,
                topics,
                "rosbag1",
            )
    except RecordingError:
        raise
    except Exception as exc:  # noqa: BLE001 - rosbags' reader errors
        raise RecordingError(f"{path}: not a readable rosbag1 ({type(exc).__name__}: {str(exc)[:200]})") from None
    return Bag(path, "rosbag1", store, types, definitions, info)


def _check_tables(db: Path, connection: sqlite3.Connection) -> None:
    """The tables rosbags queries are plain tables (read from sqlite_master, itself a table), before
    any of them is queried: a view (a recursive one never ends), a virtual table or a generated
    column (computed at each read) is refused by name."""
    kinds = dict(
        connection.execute(
            "SELECT name, CASE WHEN sql LIKE 'CREATE VIRTUAL%' THEN 'virtual table' ELSE type END "
            "FROM sqlite_master WHERE name IN (?, ?, ?, ?, ?)",
            (*SQLITE_TABLES, *SQLITE_OPTIONAL),
        ).fetchall()
    )
    for name in SQLITE_TABLES:
        if name not in kinds:
            raise RecordingError(f"{db}: no table '{name}': not a rosbag2 SQLite file")
    for name, kind in kinds.items():
        if kind != "table":
            raise RecordingError(f"{db}: '{name}' is a {kind}, not a table: not a rosbag2 SQLite file")
        generated = [c[1] for c in connection.execute(f"PRAGMA table_xinfo({name})") if c[6] in (2, 3)]
        if generated:
            raise RecordingError(f"{db}: '{name}' has generated columns ({', '.join(generated)[:80]}): refused")


def _open_sqlite(path: Path) -> Bag:
    for db in path.glob("*.db3"):
        try:
            with sqlite3.connect(f"file:{db}?mode=ro", uri=True) as connection:
                _check_tables(db, connection)
                (largest,) = connection.execute("SELECT max(length(data)) FROM messages").fetchone()
        except sqlite3.Error as exc:
            raise RecordingError(f"{db}: not a rosbag2 SQLite file ({exc})") from None
        if largest is not None and largest > MAX_MESSAGE_BYTES:
            raise RecordingError(
                f"{db}: a message of {largest / 2**20:.1f} MiB, over the cap of {MAX_MESSAGE_BYTES / 2**20:.0f} MiB"
            )
    store = typestore()
    try:
        with Rosbag2Reader(path) as bag:
            types, definitions = _connections(store, bag.connections)
            topics = [TopicInfo(c.topic, c.msgtype, c.msgcount, "cdr") for c in bag.connections]
            info = BagInfo(
                path,
                sum(p.stat().st_size for p in path.iterdir()),
                True,
                bag.start_time,
                bag.end_time,
                bag.message_count,
                topics,
                "sqlite3",
            )
    except RecordingError:
        raise
    except Exception as exc:  # noqa: BLE001 - rosbags' reader errors
        raise RecordingError(f"{path}: not a readable rosbag2 ({type(exc).__name__}: {str(exc)[:200]})") from None
    return Bag(path, "rosbag2-sqlite3", store, types, definitions, info)


def check_rosbag1(path: Path, cap: int = bounded.MAX_CHUNK_BYTES) -> None:
    """Every chunk of a rosbag1 within the cap, its data decompressing to no more than it states
    (bz2 and lz4 with a bound), before `rosbags` (which decompresses with no bound) reads it."""
    with open(path, "rb") as f:
        f.read(len(ROS1_MAGIC))
        while True:
            head = f.read(4)
            if not head:
                return
            if len(head) < 4:
                raise RecordingError(f"{path}: cut short inside a record")
            (header_len,) = struct.unpack("<I", head)
            if header_len > 1 << 20:
                raise RecordingError(f"{path}: a record header of {header_len} bytes: not a rosbag1")
            header = _ros1_header(f.read(header_len), path)
            raw = f.read(4)
            if len(raw) < 4:
                raise RecordingError(f"{path}: cut short inside a record")
            (data_len,) = struct.unpack("<I", raw)
            if data_len > bounded.MAX_RECORD_BYTES:
                raise RecordingError(
                    f"{path}: a record of {data_len / 2**20:.1f} MiB, over the cap of "
                    f"{bounded.MAX_RECORD_BYTES / 2**20:.0f} MiB"
                )
            if header.get("op") != b"\x05":  # not a chunk
                f.seek(data_len, 1)
                continue
            stated = struct.unpack("<I", header.get("size", b"\0\0\0\0")[:4].ljust(4, b"\0"))[0]
            compression = header.get("compression", b"none").decode("ascii", errors="replace")
            if stated > cap:
                raise RecordingError(
                    f"{path}: a chunk states {stated / 2**20:.1f} MiB uncompressed, over the cap of "
                    f"{cap / 2**20:.0f} MiB: refused before decompressing"
                )
            data = f.read(data_len)
            try:
                if compression == "bz2":
                    out = bz2.BZ2Decompressor().decompress(data, max_length=stated + 1)
                elif compression == "lz4":
                    out = lz4.frame.LZ4FrameDecompressor().decompress(data, max_length=stated + 1)
                elif compression == "none":
                    out = data
                else:
                    raise RecordingError(f"{path}: a chunk compressed with {compression[:20]!r} (bz2, lz4, none)")
            except (OSError, RuntimeError, EOFError, ValueError) as exc:
                raise RecordingError(f"{path}: a {compression} chunk does not decompress: {exc}") from None
            if len(out) != stated:
                raise RecordingError(
                    f"{path}: a chunk states {stated} bytes uncompressed but holds "
                    f"{'more' if len(out) > stated else len(out)}: refused"
                )


def _ros1_header(raw: bytes, path: Path) -> dict[str, bytes]:
    fields, i = {}, 0
    while i + 4 <= len(raw):
        (n,) = struct.unpack("<I", raw[i : i + 4])
        item = raw[i + 4 : i + 4 + n]
        name, sep, value = item.partition(b"=")
        if not sep:
            raise RecordingError(f"{path}: a record header field without '=': not a rosbag1")
        fields[name.decode("ascii", errors="replace")] = value
        i += 4 + n
    return fields


# --- converting ---------------------------------------------------------------------------------
def to_rosbag1(source: str | Path, target: str | Path) -> int:
    """Write any bag as a ROS 1 .bag: each message as ROS 1 has its type (the standard types from
    ROS 1's definitions, e.g. Header with its seq; a program's own from the text the bag carries),
    serialized by rosbags with ROS 1's definition and md5sum; the number of messages written."""
    bag = open_bag(source)
    target = Path(target)
    if target.exists():
        raise RecordingError(f"{target} exists: choose another name")
    ros1 = typestore(ros1=True)
    for msgtype, text in bag.definitions.items():
        if msgtype not in ros1.fielddefs:
            register(ros1, msgtype, text)
    count = 0
    with Rosbag1Writer(target) as writer:
        connections: dict[str, Any] = {}
        for m in bag.messages():
            if m.type not in ros1.fielddefs:
                continue  # the lab's foxglove scene types have no ROS definition
            if m.topic not in connections:
                connections[m.topic] = writer.add_connection(m.topic, m.type, typestore=ros1)
            message = from_json(ros1, m.type, m.data, m.topic)
            writer.write(connections[m.topic], m.log_time, ros1.serialize_ros1(message, m.type))
            count += 1
    return count
