"""app/cli/serve.py's refusals before a lab is built: a server reachable from other machines needs a
token, and a token long enough (the server itself: tests/e2e/test_cli_server.py; its limits:
tests/app/serving/test_http.py)."""

import socket
import subprocess
import sys
from pathlib import Path

from app.cli.main import main
from app.tokens import MIN_TOKEN_LENGTH, TOKEN_ENV

ROOT = Path(__file__).resolve().parents[3]


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


def test_a_taken_port_is_refused_before_the_servers_modules_are_imported():
    """A second lab on a port in use ends at once (a reader who forgot the first one): it says what
    to do, without the second or so of CPU the server's modules take to import."""
    program = (
        "import sys; from app.cli.main import main; code = main(['serve', '--view', 'none', '--port', sys.argv[1]]); "
        "print(code, sorted(m for m in ('uvicorn', 'app.serving.serve', 'app.serving.compose', 'numba') if m in sys.modules))"
    )
    with socket.create_server(("127.0.0.1", 0)) as taken:
        port = taken.getsockname()[1]
        done = subprocess.run(
            [sys.executable, "-c", program, str(port)], capture_output=True, text=True, timeout=300, cwd=ROOT
        )
    assert done.stdout.strip() == "1 []", done.stdout + done.stderr
    assert f"127.0.0.1:{port} is in use" in done.stderr
    assert "One lab per port" in done.stderr
