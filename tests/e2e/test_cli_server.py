"""`hri-lab serve` as a user starts it, and the ros2-like CLI against it (real processes, loopback)."""

import os
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

from tests.e2e.serving import running_server
from tests.http_client import http
from tests.waiting import wait_for

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    params = tmp_path_factory.mktemp("params") / "lab.yaml"
    params.write_text("keytwist:\n  ros__parameters:\n    linear_speed: 0.2\n")
    with running_server("--view", "none", "--params", str(params)) as server:
        yield server.url, server.banner


def cli(url, *args):
    env = dict(os.environ, HRI_LAB_URL=url)
    return subprocess.run([sys.executable, "-m", "app.cli", *args], capture_output=True, text=True, timeout=60, env=env)


def test_serve_prints_the_urls_and_binds_loopback(server):
    url, banner = server
    assert f"{url}/docs" in banner
    assert f"{url}/services" in banner
    assert url.startswith("http://127.0.0.1:")
    assert http.get(f"{url}/health").json()["loop_alive"] is True


def test_params_file_loaded_at_start(server):
    url, _ = server
    assert http.get(f"{url}/params/keytwist/linear_speed").json()["value"] == 0.2


def test_service_cli(server):
    url, _ = server
    out = cli(url, "service", "list", "-t").stdout
    assert "/add_two_ints [hri_lab/srv/AddTwoInts]" in out
    assert cli(url, "service", "type", "/divide_ints").stdout.strip() == "hri_lab/srv/DivideInts"
    call = cli(url, "service", "call", "/divide_ints", "{a: 1, b: 0}")
    assert call.returncode == 0
    assert "response:\nhri_lab.srv.DivideInts_Response(result=0.0, message='Division by zero!')" in call.stdout
    bad = cli(url, "service", "call", "/add_two_ints", "{a: 1, b: x}")
    assert bad.returncode == 1
    assert "b: Input should be a valid integer" in bad.stderr
    assert (
        cli(url, "service", "show", "/start_cooperative_lifting").stdout
        == "float64 force\nstring controller  # '' keeps the current one; sp or patch\n---\nstring message\n"
    )


def test_param_cli(server, tmp_path):
    url, _ = server
    assert "Double value is: 0.5" in cli(url, "param", "get", "/cooperative_lifting", "mu").stdout
    out = cli(url, "param", "set", "/cooperative_lifting", "mu", "abc")
    assert out.returncode == 1
    assert out.stdout.strip() == (
        "Setting parameter failed: Wrong parameter type, parameter {mu} is of type {double}, "
        "setting it to {string} is not allowed."
    )
    assert cli(url, "param", "set", "/cooperative_lifting", "mu", "0.6").stdout.strip() == "Set parameter successful"
    described = cli(url, "param", "describe", "/sim", "rate_hz").stdout
    assert "Type: integer" in described
    assert "Read only: true" in described
    dump = cli(url, "param", "dump", "/cooperative_lifting").stdout
    assert "mu: 0.6" in dump
    path = tmp_path / "p.yaml"
    path.write_text("cooperative_lifting:\n  ros__parameters:\n    mu: 0.5\n    f_n_min: 99.0\n")
    loaded = cli(url, "param", "load", str(path))
    assert "Set parameter mu successful" in loaded.stdout
    assert (
        "Set parameter f_n_min failed: Parameter {f_n_min} doesn't comply with floating point range." in loaded.stdout
    )
    assert "/cooperative_lifting:\n  f_n_min" in cli(url, "param", "list").stdout


def test_param_get_of_a_ros1_name_is_rosparam_get(server):
    """One name: ROS 1's parameter server, as `rosparam get /robot_description` prints it."""
    from sim.robot.assets import panda_urdf

    url, _ = server
    out = cli(url, "param", "get", "/robot_description")
    assert out.returncode == 0 and out.stdout == panda_urdf().read_text(encoding="utf-8"), out.stderr
    missing = cli(url, "param", "get", "/no_such_param")
    assert missing.returncode == 1
    assert missing.stderr.strip() == "ERROR: Parameter [/no_such_param] is not set"


def test_topic_cli(server):
    url, _ = server
    assert "/franka_state_controller/F_ext [geometry_msgs/msg/WrenchStamped]" in cli(url, "topic", "list", "-t").stdout
    echo = cli(url, "topic", "echo", "/lifting_state", "--once").stdout
    assert "started: false" in echo
    assert echo.rstrip().endswith("---")
    stream = cli(url, "topic", "echo", "/joint_states", "--rate", "20", "--count", "3").stdout
    assert stream.count("---") == 3
    assert "panda_joint7" in stream


def test_topic_echo_of_a_camera_image(server):
    """An /image_raw message (640x480 BGR, over a megabyte) is echoed whole: websockets' default
    limit of 1 MiB a message had the command fail ("message too big")."""
    url, _ = server
    image = cli(url, "topic", "echo", "/image_raw", "--count", "1")
    assert image.returncode == 0, image.stderr
    assert "height: 480" in image.stdout and "width: 640" in image.stdout and "encoding: bgr8" in image.stdout
    assert image.stdout.count("---") == 1


def test_the_client_commands_do_not_load_the_simulation():
    """`hri-lab service|param|topic|action` import neither numba nor pinocchio (nor the app's
    server): a command's module is imported when that command runs (app/cli/main.py)."""
    probe = (
        "import sys; from app.cli.main import build_parser, main; build_parser(); "
        "code = main(['service', 'list', '--url', 'http://127.0.0.1:1']); "
        "print(code, sorted(m for m in ('numba', 'pinocchio', 'fastapi', 'sim.world') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=60)
    assert out.stdout.strip() == "1 []", out.stdout + out.stderr  # exit 1: no server there


def test_cli_without_server_is_a_clear_error():
    out = cli("http://127.0.0.1:1", "service", "list")
    assert out.returncode == 1
    assert "cannot reach the hri-lab server" in out.stderr


def test_bad_params_file_refuses_to_start(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("cooperative_lifting:\n  ros__parameters:\n    mu: fast\n")
    out = subprocess.run(
        [sys.executable, "-m", "app.cli", "serve", "--port", "0", "--view", "none", "--params", str(path)],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert out.returncode == 2
    assert "Wrong parameter type, parameter {mu}" in out.stderr


def test_a_client_that_never_reads_does_not_stall_the_loop(server):
    """A WebSocket client asks for 1 kHz of joint states and never reads: its socket buffers fill,
    the server drops what it cannot send, and the simulation keeps its pace."""
    from websockets.sync.client import connect

    url, _ = server
    ws_url = url.replace("http://", "ws://") + "/topics/joint_states/stream?rate=1000"

    def advance(seconds):
        t0, w0 = http.get(f"{url}/health").json()["sim_time"], time.monotonic()
        time.sleep(seconds)
        t1, w1 = http.get(f"{url}/health").json()["sim_time"], time.monotonic()
        return (t1 - t0) / (w1 - w0)

    baseline = advance(1.0)
    # close_timeout: the stuck client's close frame waits behind what it never read (its own end)
    with connect(ws_url, max_size=2**20, close_timeout=1) as ws:
        ws.socket.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        loaded = advance(2.0)
    # simulated seconds per wall second with the stuck client, relative to without it
    assert loaded > 0.5 * baseline, (baseline, loaded)
    assert http.get(f"{url}/health").json()["loop_alive"] is True
    # a client that disconnects mid-stream leaves nothing behind either
    with connect(ws_url) as ws:
        ws.recv()
    assert http.get(f"{url}/topics/joint_states").status_code == 200


def test_action_cli(server):
    url, _ = server
    assert "/count [hri_lab/action/Count]" in cli(url, "action", "list", "-t").stdout
    out = cli(url, "action", "send_goal", "/count", "{count: 2}", "--feedback")
    assert out.returncode == 0, out.stderr
    assert "Goal accepted with ID:" in out.stdout
    assert out.stdout.count("Feedback:") == 2
    assert "current_number: 2" in out.stdout
    assert "Result:\n    final_count: 2" in out.stdout
    assert out.stdout.rstrip().endswith("Goal finished with status: SUCCEEDED")
    bad = cli(url, "action", "send_goal", "/count", "{count: -3}")
    assert bad.returncode == 1
    assert "count" in bad.stderr


def test_ctrl_c_stops_the_lab_without_a_traceback():
    """Ctrl+C in `hri-lab serve`'s terminal (SIGINT to its process group): the lab stops, exit 0,
    and the terminal shows no traceback (uvicorn re-raises the signal once it has shut down)."""
    import signal

    from app.serving.launch import free_port

    port = free_port()
    serve = subprocess.Popen(
        [sys.executable, "-m", "app.cli", "serve", "--view", "none", "--port", str(port), "--output-dir", "."],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        start_new_session=True,
        cwd=tempfile.mkdtemp(),
    )
    try:
        wait_for(lambda: _answers(f"http://127.0.0.1:{port}/health"), timeout=180)
        os.killpg(serve.pid, signal.SIGINT)
        output, _ = serve.communicate(timeout=60)
    finally:
        if serve.poll() is None:
            serve.kill()
            serve.wait()
    assert serve.returncode == 0, output
    assert "Traceback" not in output and "KeyboardInterrupt" not in output, output


def _answers(url: str) -> bool:
    try:
        return http.get(url, timeout=5).status_code == 200
    except Exception:  # noqa: BLE001 - not listening yet
        return False


def test_a_taken_port_is_refused_before_the_servers_modules_are_imported():
    """A second lab on a port in use ends at once (a reader who forgot the first one): it says what
    to do, without the second or so of CPU the server's modules take to import (app/cli/serve.py)."""
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
