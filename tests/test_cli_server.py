"""`hri-lab serve` as a user starts it, and the ros2-like CLI against it (real processes, loopback)."""
import os
import socket
import subprocess
import sys
import time

import httpx
import pytest


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    params = tmp_path_factory.mktemp("params") / "lab.yaml"
    params.write_text("keytwist:\n  ros__parameters:\n    linear_speed: 0.2\n")
    port = free_port()
    proc = subprocess.Popen(
        [sys.executable, "-m", "app.cli", "serve", "--port", str(port), "--params", str(params)],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
    )
    url = f"http://127.0.0.1:{port}"
    lines = []
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        line = proc.stdout.readline()
        lines.append(line)
        if "Press Ctrl+C" in line or proc.poll() is not None:
            break
    assert proc.poll() is None, "".join(lines)
    yield url, "".join(lines)
    proc.terminate()
    proc.wait(timeout=10)


def cli(url, *args):
    env = dict(os.environ, HRI_LAB_URL=url)
    return subprocess.run([sys.executable, "-m", "app.cli", *args], capture_output=True, text=True, timeout=60, env=env)


def test_serve_prints_the_urls_and_binds_loopback(server):
    url, banner = server
    assert f"{url}/docs" in banner and f"{url}/services" in banner
    assert url.startswith("http://127.0.0.1:")
    assert httpx.get(f"{url}/health").json()["loop_alive"] is True


def test_params_file_loaded_at_start(server):
    url, _ = server
    assert httpx.get(f"{url}/params/keytwist/linear_speed").json()["value"] == 0.2


def test_service_cli(server):
    url, _ = server
    out = cli(url, "service", "list", "-t").stdout
    assert "/add_two_ints [hri_lab/AddTwoInts]" in out
    assert cli(url, "service", "type", "/divide_ints").stdout.strip() == "hri_lab/DivideInts"
    call = cli(url, "service", "call", "/divide_ints", "{a: 1, b: 0}")
    assert call.returncode == 0
    assert "response:\nhri_lab.DivideInts_Response(result=0.0, message='Division by zero!')" in call.stdout
    bad = cli(url, "service", "call", "/add_two_ints", "{a: 1, b: x}")
    assert bad.returncode == 1 and "b: Input should be a valid integer" in bad.stderr
    assert cli(url, "service", "show", "/start_cooperative_lifting").stdout == "float64 force\n---\nstring message\n"


def test_param_cli(server, tmp_path):
    url, _ = server
    assert "Double value is: 0.5" in cli(url, "param", "get", "/cooperative_lifting", "mu").stdout
    out = cli(url, "param", "set", "/cooperative_lifting", "mu", "abc")
    assert out.returncode == 1
    assert out.stdout.strip() == ("Setting parameter failed: Wrong parameter type, parameter {mu} is of type {double}, "
                                  "setting it to {string} is not allowed.")
    assert cli(url, "param", "set", "/cooperative_lifting", "mu", "0.6").stdout.strip() == "Set parameter successful"
    described = cli(url, "param", "describe", "/sim", "rate_hz").stdout
    assert "Type: integer" in described and "Read only: true" in described
    dump = cli(url, "param", "dump", "/cooperative_lifting").stdout
    assert "mu: 0.6" in dump
    path = tmp_path / "p.yaml"
    path.write_text("cooperative_lifting:\n  ros__parameters:\n    mu: 0.5\n    f_n_min: 99.0\n")
    loaded = cli(url, "param", "load", str(path))
    assert "Set parameter mu successful" in loaded.stdout
    assert "Set parameter f_n_min failed: Parameter {f_n_min} doesn't comply with floating point range." in loaded.stdout
    assert "/cooperative_lifting:\n  f_n_min" in cli(url, "param", "list").stdout


def test_topic_cli(server):
    url, _ = server
    assert "/franka_state_controller/F_ext [geometry_msgs/WrenchStamped]" in cli(url, "topic", "list", "-t").stdout
    echo = cli(url, "topic", "echo", "/lifting_state").stdout
    assert "started: false" in echo and echo.rstrip().endswith("---")


def test_cli_without_server_is_a_clear_error():
    out = cli("http://127.0.0.1:1", "service", "list")
    assert out.returncode == 1 and "cannot reach the hri-lab server" in out.stderr


def test_bad_params_file_refuses_to_start(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("cooperative_lifting:\n  ros__parameters:\n    mu: fast\n")
    out = subprocess.run([sys.executable, "-m", "app.cli", "serve", "--port", str(free_port()), "--params", str(path)],
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 2 and "Wrong parameter type, parameter {mu}" in out.stderr
