"""app/worlds/port.py: both labs, the lifting one and the mobile one, are what LabPort says a lab is
(mypy checks Lab where LabEvents takes it; this checks both at run time, attribute by attribute)."""

import pytest

from app.lab.lab import Lab
from app.mobile.lab import MobileLab
from app.ros.params import ParameterServer
from app.worlds.port import LabPort


@pytest.mark.parametrize("make", [lambda: Lab(realtime=False), lambda: MobileLab(realtime=False)])
def test_both_labs_are_lab_ports(make):
    lab = make()  # not started: no process runs
    assert isinstance(lab, LabPort)
    assert isinstance(lab.params, ParameterServer)
    assert lab.params.lab is lab


def test_an_object_missing_a_member_is_not_a_lab_port():
    class NoNeeds:
        runtime = rosout = params = param_tree = recordings_dir = figures_dir = None

        def start(self): ...
        def stop(self): ...
        def snapshot(self): ...
        def call(self, fn, *args, timeout=10.0): ...
        def submit(self, fn, *args): ...
        def info(self, node, message): ...

    assert not isinstance(NoNeeds(), LabPort)
