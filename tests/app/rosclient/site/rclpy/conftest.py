"""rclpy imported as a program imports it (the site fixture), initialised over a RecordingConnection
(tests/app/rosclient/site/conftest.py)."""

from __future__ import annotations

import pytest

from app.rosclient import process
from tests.app.rosclient.site.conftest import RecordingConnection


@pytest.fixture()
def rclpy(site):
    """rclpy, initialised; `rclpy.connection` is the lab's side."""
    connection = RecordingConnection()
    process._connection.append(connection)
    import rclpy as module

    module.init(args=["program"], signal_handler_options=0)
    module.connection = connection
    return module
