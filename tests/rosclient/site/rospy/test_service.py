"""rospy's Service (rosclient/site/rospy/impl/tcpros_service.py): its spin() returns when the
service is shut down or the node is, as rospy's ServiceImpl.spin does (Debian's python3-rospy,
rospy/impl/tcpros_service.py: `while not rospy.core.is_shutdown() and not self.done`)."""

from __future__ import annotations

import threading

import pytest

from rosclient import process
from tests.rosclient.site.conftest import RecordingConnection


@pytest.fixture
def lab(site):
    connection = RecordingConnection()
    process._connection.append(connection)
    return connection


def spinning(service) -> threading.Thread:
    thread = threading.Thread(target=service.spin, daemon=True)
    thread.start()
    return thread


def test_spin_returns_when_the_service_shuts_down(lab):
    import rospy
    from example_interfaces.srv import AddTwoInts

    service = rospy.Service("/add_two_ints", AddTwoInts, lambda request: request.a + request.b)
    thread = spinning(service)
    thread.join(0.5)
    assert thread.is_alive()  # served: spin() waits
    service.shutdown("done")
    thread.join(60)
    assert not thread.is_alive()
    assert lab.sent[-1] == {"op": "unadvertise_service", "service": "/add_two_ints"}


def test_spin_returns_when_the_node_shuts_down(lab):
    import rospy
    from example_interfaces.srv import AddTwoInts

    service = rospy.Service("/add_two_ints", AddTwoInts, lambda request: request.a + request.b)
    try:
        thread = spinning(service)
        process.shutdown_event.set()
        thread.join(60)
        assert not thread.is_alive()
    finally:
        service.shutdown()
