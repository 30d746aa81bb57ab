"""app/serving/http.py: the server's limits in uvicorn's configuration (the server itself:
tests/e2e/test_cli_server.py, tests/e2e/test_hardening.py, tests/e2e/test_limits.py)."""

from app.rosbridge.protocol import MAX_FRAME
from app.serving.http import KEEP_ALIVE_S, READ_TIMEOUT_S, SHUTDOWN_S, WS_PING_TIMEOUT_S, server_config


def test_uvicorn_gets_the_servers_limits():
    config = server_config(app=None, host="127.0.0.1", port=8123)
    assert (config.host, config.port) == ("127.0.0.1", 8123)
    assert config.timeout_keep_alive == KEEP_ALIVE_S
    assert config.timeout_graceful_shutdown == SHUTDOWN_S
    assert config.ws_max_size == 2 * MAX_FRAME
    assert config.ws_ping_timeout == WS_PING_TIMEOUT_S
    assert config.ws_per_message_deflate is False  # rosbridge_server's default: no compression
    assert config.http.read_timeout_s == READ_TIMEOUT_S
    assert server_config(None, "127.0.0.1", 1, read_timeout_s=0.5).http.read_timeout_s == 0.5
