"""rclpy imported as a program imports it (the site fixture), initialised over a RecordingConnection
(tests/rosclient/site/conftest.py)."""

from __future__ import annotations

import pytest

from rosclient import process
from tests.rosclient.site.conftest import RecordingConnection


@pytest.fixture()
def rclpy(site):
    """rclpy, initialised; `rclpy.connection` is the lab's side."""
    connection = RecordingConnection()
    process._connection.append(connection)
    import rclpy as module

    module.init(args=["program"], signal_handler_options=0)
    module.connection = connection
    return module
