"""app/cli/serve.py's refusals before a lab is built (a server reachable from other machines
needs a token, and a token long enough) and the server's limits in uvicorn's configuration (the
server itself: tests/e2e/test_cli_server.py, tests/e2e/test_hardening.py)."""

from app.cli.main import main
from app.cli.serve import KEEP_ALIVE_S, READ_TIMEOUT_S, SHUTDOWN_S, WS_PING_TIMEOUT_S, server_config
from app.rosbridge.protocol import MAX_FRAME
from app.tokens import MIN_TOKEN_LENGTH, TOKEN_ENV


def test_a_server_for_other_machines_needs_a_token(monkeypatch, capsys):
    monkeypatch.delenv(TOKEN_ENV, raising=False)
    assert main(["serve", "--host", "0.0.0.0", "--view", "none"]) == 2
    err = capsys.readouterr().err
    assert f"binding 0.0.0.0 (not this machine only) needs a token: --token or ${TOKEN_ENV}" in err
    assert "inside a container whose port the host publishes on its loopback: --no-token" in err


def test_a_short_token_is_refused(monkeypatch, capsys):
    monkeypatch.delenv(TOKEN_ENV, raising=False)
    assert main(["serve", "--view", "none", "--token", "x" * (MIN_TOKEN_LENGTH - 1)]) == 2
    assert f"at least {MIN_TOKEN_LENGTH} characters" in capsys.readouterr().err


def test_uvicorn_gets_the_servers_limits():
    config = server_config(app=None, host="127.0.0.1", port=8123)
    assert (config.host, config.port) == ("127.0.0.1", 8123)
    assert config.timeout_keep_alive == KEEP_ALIVE_S
    assert config.timeout_graceful_shutdown == SHUTDOWN_S
    assert config.ws_max_size == 2 * MAX_FRAME
    assert config.ws_ping_timeout == WS_PING_TIMEOUT_S
    assert config.http.read_timeout_s == READ_TIMEOUT_S
    assert server_config(None, "127.0.0.1", 1, read_timeout_s=0.5).http.read_timeout_s == 0.5
