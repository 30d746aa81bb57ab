"""app/cli/serve.py's refusals before a lab is built: a server reachable from other machines needs a
token, and a token long enough (the server itself: tests/e2e/test_cli_server.py; its limits:
tests/app/serving/test_http.py)."""

from app.cli.main import main
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
