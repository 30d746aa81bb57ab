"""The import finder of a program's process (rosclient/interfaces.py): `<pkg>.msg|srv|action`
modules with genpy's names, and cv_bridge over the classes it makes."""

import subprocess
import sys
from pathlib import Path

import pytest

from interfaces.packages import Interfaces
from tests.ros_running import PROGRAMS


def test_actionlib_names_of_an_action_in_msg_and_action(tmp_path):
    import importlib
    import sys

    from rosclient.interfaces import Finder

    finder = Finder(Interfaces([PROGRAMS]))
    sys.meta_path.insert(0, finder)
    try:
        msg = importlib.import_module("cpp_package.msg")
        action = importlib.import_module("cpp_package.action")
        assert msg.CountingGoal is action.Counting.Goal
        assert action.CountingAction is msg.CountingAction
        assert msg.CountingAction.Goal is action.Counting.Goal  # actionlib's ActionSpec names its parts
        assert msg.CountingAction._action_type == "cpp_package/action/Counting"
        srv = importlib.import_module("cpp_package.srv")
        assert srv.MultiplyThreeRequest(1, 2, 3).c == 3

        # what `from cpp_package.srv import *` and `from cpp_package.msg import *` bind: each name of __all__
        namespace = {name: getattr(module, name) for module in (srv, msg) for name in module.__all__}
        assert {"MultiplyThree", "MultiplyThreeRequest", "MultiplyThreeResponse"} <= set(namespace)
        assert namespace["MultiplyThreeResponse"] is srv.MultiplyThree.Response
        assert {"CountingAction", "CountingActionGoal", "CountingActionResult", "CountingActionFeedback",
                "CountingGoal", "CountingResult", "CountingFeedback"} <= set(namespace)  # fmt: skip
    finally:
        sys.meta_path.remove(finder)
        for name in [m for m in sys.modules if m.startswith("cpp_package")]:
            del sys.modules[name]


def test_cv_bridge_converts_images_as_cv_bridge_does():
    import sys

    import numpy as np

    from rosclient import boot
    from rosclient.interfaces import Finder

    finder = Finder(Interfaces([]))
    sys.meta_path.insert(0, finder)
    sys.path.insert(0, str(boot.SITE))
    try:
        from cv_bridge import CvBridge, CvBridgeError

        bridge = CvBridge()
        rgb = np.zeros((2, 3, 3), np.uint8)
        rgb[0, 0] = (255, 0, 0)  # red
        msg = bridge.cv2_to_imgmsg(rgb, "rgb8")
        assert (msg.height, msg.width, msg.step, msg.encoding) == (2, 3, 9, "rgb8")
        bgr = bridge.imgmsg_to_cv2(type(msg).from_json(msg.to_json()), "bgr8")  # through rosbridge's JSON
        assert tuple(bgr[0, 0]) == (0, 0, 255)
        assert bgr.shape == (2, 3, 3)
        assert bridge.imgmsg_to_cv2(msg, "mono8")[0, 0] == 76  # 0.299 * 255, OpenCV's weights
        with pytest.raises(CvBridgeError, match="incompatible"):
            bridge.cv2_to_imgmsg(rgb, "mono8")
    finally:
        sys.path.remove(str(boot.SITE))
        sys.meta_path.remove(finder)
        for name in [
            m for m in sys.modules if m.split(".")[0] in ("cv_bridge", "sensor_msgs", "std_msgs", "builtin_interfaces")
        ]:
            del sys.modules[name]


def test_point_cloud2_packs_and_reads_points_as_ros1s_module():
    import math
    import sys

    from rosclient import boot
    from rosclient.interfaces import Finder

    finder = Finder(Interfaces([]))
    sys.meta_path.insert(0, finder)
    sys.path.insert(0, str(boot.SITE))
    try:
        from sensor_msgs import point_cloud2
        from sensor_msgs.msg import PointCloud2, PointField
        from std_msgs.msg import Header

        cloud = point_cloud2.create_cloud_xyz32(Header(frame_id="map"), [(1.0, 2.0, 3.0), (0.5, math.nan, -1.0)])
        assert (cloud.width, cloud.height, cloud.point_step, cloud.row_step) == (2, 1, 12, 24)
        assert cloud.data[:4] == bytes.fromhex("0000803f")  # 1.0 as a little-endian float32
        sent = PointCloud2.from_json(cloud.to_json())  # through rosbridge's JSON (data as base64)
        assert list(point_cloud2.read_points(sent, skip_nans=True)) == [(1.0, 2.0, 3.0)]
        assert point_cloud2.read_points_list(sent, field_names=["z"])[1].z == -1.0
        rgb = [PointField("x", 0, PointField.FLOAT32, 1), PointField("rgb", 8, PointField.UINT32, 1)]  # a gap
        packed = point_cloud2.create_cloud(Header(), rgb, [(0.25, 0xFF0000)])
        assert packed.point_step == 12
        assert list(point_cloud2.read_points(packed)) == [(0.25, 0xFF0000)]
    finally:
        sys.path.remove(str(boot.SITE))
        sys.meta_path.remove(finder)
        for name in [m for m in sys.modules if m.split(".")[0] in ("sensor_msgs", "std_msgs", "builtin_interfaces")]:
            del sys.modules[name]


def test_a_broken_msg_stops_the_program_with_one_line_naming_the_file_and_line(tmp_path):
    """`hri-lab run` of a program that imports a broken .msg: one line, not a 25-line traceback."""
    msg = tmp_path / "my_pkg" / "msg"
    msg.mkdir(parents=True)
    (msg / "Bad.msg").write_text("int32 a\nint32[ broken b\n")
    (tmp_path / "my_pkg" / "package.xml").write_text("<package><name>my_pkg</name></package>\n")
    (tmp_path / "prog.py").write_text("from my_pkg.msg import Bad\nprint(Bad())\n")
    done = subprocess.run(
        [sys.executable, "-m", "rosclient.boot", str(tmp_path / "prog.py")],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=Path(__file__).resolve().parents[3],
    )
    assert done.returncode == 1
    assert done.stderr.splitlines() == [
        f"[FATAL] {msg / 'Bad.msg'}, line 2: expected 'TYPE NAME', 'TYPE NAME DEFAULT' or 'TYPE NAME=VALUE' "
        "(e.g. 'int64 a'), got 'int32[ broken b'"
    ]
