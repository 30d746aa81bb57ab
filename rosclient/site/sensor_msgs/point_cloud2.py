"""sensor_msgs.point_cloud2: PointCloud2 messages from points and back, as ROS 1's module offers
them (create_cloud, create_cloud_xyz32, read_points, read_points_list); each point packed with
`struct` in the fields' layout."""

from __future__ import annotations

import math
import struct
from collections import namedtuple
from collections.abc import Iterable, Iterator, Sequence
from typing import Any

from sensor_msgs.msg import PointCloud2, PointField

# PointField's datatype -> (struct's format character, size in bytes)
DATATYPES = {
    PointField.INT8: ("b", 1),
    PointField.UINT8: ("B", 1),
    PointField.INT16: ("h", 2),
    PointField.UINT16: ("H", 2),
    PointField.INT32: ("i", 4),
    PointField.UINT32: ("I", 4),
    PointField.FLOAT32: ("f", 4),
    PointField.FLOAT64: ("d", 8),
}


def _struct_fmt(is_bigendian: bool, fields: Sequence[Any], field_names: Sequence[str] | None = None) -> str:
    """The struct format of one point: each wanted field at its offset, the bytes between skipped."""
    fmt = ">" if is_bigendian else "<"
    offset = 0
    for field in sorted(fields, key=lambda f: f.offset):
        if field_names is not None and field.name not in field_names:
            continue
        if field.datatype not in DATATYPES:
            raise ValueError(f"point field {field.name!r}: unknown datatype {field.datatype}")
        if offset < field.offset:
            fmt += "x" * (field.offset - offset)
            offset = field.offset
        char, size = DATATYPES[field.datatype]
        fmt += char * field.count
        offset += size * field.count
    return fmt


def create_cloud(header: Any, fields: Sequence[Any], points: Iterable[Sequence[float]]) -> Any:
    """A PointCloud2 of one row holding `points` (each a sequence of the fields' values)."""
    cloud_struct = struct.Struct(_struct_fmt(False, fields))
    rows = list(points)
    buffer = bytearray(cloud_struct.size * len(rows))
    for i, point in enumerate(rows):
        cloud_struct.pack_into(buffer, i * cloud_struct.size, *point)
    return PointCloud2(
        header=header,
        height=1,
        width=len(rows),
        is_dense=False,
        is_bigendian=False,
        fields=list(fields),
        point_step=cloud_struct.size,
        row_step=cloud_struct.size * len(rows),
        data=bytes(buffer),
    )


def create_cloud_xyz32(header: Any, points: Iterable[Sequence[float]]) -> Any:
    """A PointCloud2 of x, y, z float32 points."""
    fields = [
        PointField("x", 0, PointField.FLOAT32, 1),
        PointField("y", 4, PointField.FLOAT32, 1),
        PointField("z", 8, PointField.FLOAT32, 1),
    ]
    return create_cloud(header, fields, points)


def read_points(
    cloud: Any,
    field_names: Sequence[str] | None = None,
    skip_nans: bool = False,
    uvs: Sequence[tuple[int, int]] = (),
) -> Iterator[tuple[Any, ...]]:
    """Each point's values (of `field_names`, else every field) as a tuple, row by row; `uvs`: only
    the points at these (column, row); `skip_nans`: without the points that have a NaN."""
    fmt = _struct_fmt(cloud.is_bigendian, cloud.fields, field_names)
    unpack = struct.Struct(fmt).unpack_from
    data = bytes(cloud.data)
    places = list(uvs) or [(u, v) for v in range(cloud.height) for u in range(cloud.width)]
    for u, v in places:
        point = unpack(data, v * cloud.row_step + u * cloud.point_step)
        if skip_nans and any(isinstance(x, float) and math.isnan(x) for x in point):
            continue
        yield point


def read_points_list(
    cloud: Any,
    field_names: Sequence[str] | None = None,
    skip_nans: bool = False,
    uvs: Sequence[tuple[int, int]] = (),
) -> list[Any]:
    """read_points as a list of named tuples (the fields' names)."""
    names = list(field_names) if field_names is not None else [f.name for f in cloud.fields]
    make_type: Any = namedtuple  # the fields' names are the cloud's, known only now
    point_type = make_type("Point", names)
    return [point_type._make(p) for p in read_points(cloud, field_names, skip_nans, uvs)]
