"""app/serving/launch.py's free port (the servers the tests and benchmarks start: tests/e2e/serving.py
starts them with ServerProcess, and every end-to-end test is its check)."""

import socket

from app.serving.launch import free_port


def test_a_free_port_can_be_bound_on_the_loopback():
    port = free_port()
    assert 1024 <= port <= 65535
    with socket.socket() as s:
        s.bind(("127.0.0.1", port))  # free: nothing holds it after free_port returns
