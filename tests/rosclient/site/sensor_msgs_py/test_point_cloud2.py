"""sensor_msgs_py.point_cloud2 (rosclient/site/sensor_msgs_py/point_cloud2.py): a cloud made of
points lays them out as its PointFields say (offsets, point_step, little-endian float32) and reads
back the same values; NaN points are skipped when asked."""

import math
import struct

import numpy as np


def test_a_cloud_lays_its_points_out_by_its_fields_and_reads_them_back(site):
    from sensor_msgs.msg import PointField
    from sensor_msgs_py import point_cloud2
    from std_msgs.msg import Header

    fields = [PointField(name=n, offset=4 * i, datatype=PointField.FLOAT32, count=1) for i, n in enumerate("xyz")]
    fields.append(PointField(name="intensity", offset=12, datatype=PointField.FLOAT32, count=1))
    points = np.array([[1.0, 2.0, 3.0, 0.5], [-1.0, 0.25, math.nan, 1.0]])
    cloud = point_cloud2.create_cloud(Header(frame_id="map"), fields, points)
    assert (cloud.width, cloud.height, cloud.point_step, cloud.row_step) == (2, 1, 16, 32)
    assert struct.unpack("<4f", bytes(cloud.data)[:16]) == (1.0, 2.0, 3.0, 0.5)
    back = point_cloud2.read_points(cloud, field_names=("x", "y"))
    assert back["x"].tolist() == [1.0, -1.0] and back["y"].tolist() == [2.0, 0.25]
    assert point_cloud2.read_points_list(cloud, skip_nans=True) == [(1.0, 2.0, 3.0, 0.5)]
    xyz = point_cloud2.create_cloud_xyz32(Header(), [(0.0, 1.0, 2.0)])
    assert point_cloud2.read_points_numpy(xyz).tolist() == [[0.0, 1.0, 2.0]]
