"""sensor_msgs_py.point_cloud2 as ROS 2 has it: a PointCloud2 made from points (`create_cloud`,
`create_cloud_xyz32`) and read back (`read_points` as a numpy structured array, `read_points_list`,
`read_points_numpy`), each point laid out by the message's PointFields (little-endian)."""

from __future__ import annotations

from collections import namedtuple
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np

# PointField.datatype -> numpy's type
DATATYPES = {1: np.int8, 2: np.uint8, 3: np.int16, 4: np.uint16, 5: np.int32, 6: np.uint32, 7: np.float32, 8: np.float64}


def dtype_from_fields(fields: Iterable[Any], point_step: int | None = None) -> np.dtype:
    names: list[str] = []
    formats: list[Any] = []
    offsets: list[int] = []
    for field in fields:
        if field.datatype not in DATATYPES:
            raise ValueError(f"PointField {field.name!r}: unknown datatype {field.datatype}")
        base = np.dtype(DATATYPES[field.datatype]).newbyteorder("<")
        names.append(field.name)
        formats.append(base if field.count <= 1 else (base, (field.count,)))
        offsets.append(field.offset)
    if point_step is None:
        return np.dtype({"names": names, "formats": formats, "offsets": offsets})
    return np.dtype({"names": names, "formats": formats, "offsets": offsets, "itemsize": point_step})


def create_cloud(header: Any, fields: Sequence[Any], points: Any, point_step: int | None = None) -> Any:
    """A PointCloud2 (one row) of `points`: a 2-D array or a list of tuples, one value per field."""
    from sensor_msgs.msg import PointCloud2

    dtype = dtype_from_fields(fields, point_step)
    if isinstance(points, np.ndarray) and points.dtype.names is not None:
        cloud = points.astype(dtype).reshape(-1)
    else:
        array = points.reshape(len(points), -1) if isinstance(points, np.ndarray) else points
        rows = [tuple(p) for p in array]
        cloud = np.zeros(len(rows), dtype=dtype)
        for i, name in enumerate(dtype.names or ()):
            cloud[name] = [row[i] for row in rows]
    return PointCloud2(
        header=header,
        height=1,
        width=len(cloud),
        is_dense=False,
        is_bigendian=False,
        fields=list(fields),
        point_step=dtype.itemsize,
        row_step=dtype.itemsize * len(cloud),
        data=cloud.tobytes(),
    )


def create_cloud_xyz32(header: Any, points: Any) -> Any:
    from sensor_msgs.msg import PointField

    fields = [PointField(name=axis, offset=4 * i, datatype=PointField.FLOAT32, count=1) for i, axis in enumerate("xyz")]
    return create_cloud(header, fields, points)


def read_points(cloud: Any, field_names: Sequence[str] | None = None, skip_nans: bool = False, uvs: Any = None,
                reshape_organized_cloud: bool = False) -> np.ndarray:
    """The points as a structured array (the fields asked for), NaN points left out with skip_nans."""
    if cloud.is_bigendian:
        raise ValueError("read_points: big-endian clouds are not read here")
    points = np.frombuffer(bytes(cloud.data), dtype=dtype_from_fields(cloud.fields, cloud.point_step))
    if field_names is not None:
        points = points[list(field_names)]
    if skip_nans:
        names = points.dtype.names or ()
        keep = np.ones(len(points), dtype=bool)
        for name in names:
            values = points[name]
            if values.dtype.kind == "f":
                keep &= ~np.isnan(values.reshape(len(points), -1)).any(axis=1)
        points = points[keep]
    if uvs is not None:
        points = points[np.asarray([int(v) * cloud.width + int(u) for u, v in uvs], dtype=int)]
    if reshape_organized_cloud and cloud.height > 1:
        points = points.reshape(cloud.height, cloud.width)
    return points


def read_points_numpy(cloud: Any, field_names: Sequence[str] | None = None, skip_nans: bool = False) -> np.ndarray:
    points = read_points(cloud, field_names, skip_nans)
    return np.column_stack([points[name] for name in points.dtype.names or ()])


def read_points_list(cloud: Any, field_names: Sequence[str] | None = None, skip_nans: bool = False) -> list[Any]:
    points = read_points(cloud, field_names, skip_nans)
    factory: Any = namedtuple  # the fields are the cloud's, known only now
    Point = factory("Point", points.dtype.names or ())
    return [Point(*row) for row in points.tolist()]
