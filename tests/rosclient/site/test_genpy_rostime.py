"""genpy's Time and Duration (rosclient/site/genpy/rostime.py): canonical secs/nsecs, genpy's
arithmetic, and a message's time and duration fields (builtin_interfaces) taken as genpy's."""

import importlib.util

import pytest

from interfaces.packages import Interfaces
from rosclient import boot


@pytest.fixture
def rostime():
    spec = importlib.util.spec_from_file_location("genpy_rostime_under_test", boot.SITE / "genpy" / "rostime.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_time_and_duration_are_canonical_and_add_as_genpys(rostime):
    t = rostime.Time(1, 1_500_000_000)
    assert (t.secs, t.nsecs) == (2, 500_000_000) and t.to_sec() == 2.5
    d = rostime.Duration(-1, 250_000_000)  # -0.75 s: nsecs keeps the sign of the whole
    assert (d.secs, d.nsecs) == (0, -750_000_000) and d.to_sec() == -0.75
    assert (t + rostime.Duration(0.5)).to_nsec() == 3_000_000_000
    assert isinstance(t - rostime.Time(1), rostime.Duration) and (t - rostime.Time(1)).to_sec() == 1.5
    assert rostime.Duration(3) / rostime.Duration(2) == 1.5 and (rostime.Duration(3) * 2).secs == 6
    with pytest.raises(ValueError, match="positive"):
        rostime.Time(-1)
    with pytest.raises(ValueError, match="nsecs cannot be set"):
        rostime.Time(1.5, 3)


def test_a_messages_time_and_duration_fields_take_part(rostime):
    duration = Interfaces([]).message("builtin_interfaces/Duration")(sec=2, nanosec=5)
    stamp = Interfaces([]).message("builtin_interfaces/Time")(sec=10, nanosec=0)
    assert (rostime.Time(1) + duration).to_nsec() == 3_000_000_005  # actionlib's mock server's deadline
    assert (rostime.Time(12) - stamp).to_sec() == 2.0 and isinstance(rostime.Time(12) - stamp, rostime.Duration)
    assert (rostime.Time(12) - duration).secs == 9
    assert (rostime.Duration(1) + duration).to_nsec() == 3_000_000_005
