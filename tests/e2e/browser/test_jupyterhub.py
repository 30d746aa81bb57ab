"""The lab in a student's Jupyter server behind a real JupyterHub (app/jupyter_proxy.py, docs/hosting.md):
one hub for the module (npm's configurable-http-proxy, DummyAuthenticator with a password,
SimpleLocalProcessSpawner), two students. Ada opens her lab from the launcher's URL in Chromium and
sees it live (the dashboard and the 3D view, through the hub's proxy); her terminal's environment
reaches it (roslibpy and the CLI, with her hub token); Bob gets a 403 on every URL of it; stopping
her server leaves no lab process."""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import httpx
import pytest
import roslibpy
import websockets.exceptions
from websockets.sync.client import connect

from app.serving.launch import free_port
from bench.page_responsiveness import ARGS, CHROMIUM, CONTROL_PANEL_TAB
from tests.http_client import http
from tests.waiting import process_gone, wait_for

ROOT = Path(__file__).resolve().parents[3]
BIN = Path(sys.executable).parent
CHP = ROOT / ".venv" / "chp" / "node_modules" / ".bin" / "configurable-http-proxy"  # the Makefile's $(CHP)
PASSWORD = "a-course-password"
ADMIN_TOKEN = "test-service-token-0123456789abcdef"
F_EXT = "/franka_state_controller/F_ext"


def _config(tmp: Path, port: int) -> str:
    return textwrap.dedent(f"""
        c.JupyterHub.bind_url = "http://127.0.0.1:{port}"
        c.JupyterHub.hub_ip = "127.0.0.1"
        c.JupyterHub.hub_port = {free_port()}
        c.ConfigurableHTTPProxy.command = [{str(CHP)!r}]
        c.ConfigurableHTTPProxy.api_url = "http://127.0.0.1:{free_port()}"
        c.ConfigurableHTTPProxy.should_start = True
        c.JupyterHub.db_url = "sqlite:///{tmp}/hub.sqlite"
        c.JupyterHub.cookie_secret_file = "{tmp}/cookie_secret"
        c.JupyterHub.pid_file = "{tmp}/hub.pid"
        c.JupyterHub.authenticator_class = "dummy"
        c.DummyAuthenticator.password = {PASSWORD!r}
        c.Authenticator.allowed_users = {{"ada", "bob"}}
        c.Authenticator.admin_users = {{"instructor"}}
        c.JupyterHub.spawner_class = "simple"
        c.SimpleLocalProcessSpawner.home_dir_template = "{tmp}/home/{{username}}"
        c.Spawner.cmd = [{str(BIN / "jupyterhub-singleuser")!r}]
        c.Spawner.args = ["--ServerApp.allow_root=True"]  # the test machine runs as root
        c.Spawner.environment = {{"HRI_LAB_VIEW": "light"}}  # Chromium renders the view in software here
        c.Spawner.start_timeout = 180
        c.Spawner.http_timeout = 180
        c.JupyterHub.cleanup_servers = True
        c.JupyterHub.services = [{{"name": "course", "api_token": {ADMIN_TOKEN!r}}}]
        c.JupyterHub.load_roles = [{{"name": "course", "scopes": ["admin:users", "admin:servers", "tokens"], "services": ["course"]}}]
    """)


class Hub:
    def __init__(self, url: str, process: subprocess.Popen) -> None:
        self.url, self.process = url, process
        self.api = httpx.Client(
            base_url=f"{url}/hub/api", headers={"Authorization": f"token {ADMIN_TOKEN}"}, timeout=60
        )

    def start_server(self, user: str) -> None:
        answer = self.api.post(f"/users/{user}/server")
        assert answer.status_code in (201, 202), answer.text
        wait_for(lambda: self.api.get(f"/users/{user}").json()["servers"].get("", {}).get("ready"), timeout=240)

    def token(self, user: str) -> str:
        """A new API token of `user`'s (what a student makes on the hub's token page)."""
        answer = self.api.post(f"/users/{user}/tokens", json={"note": "test"})
        assert answer.status_code == 201, answer.text
        return answer.json()["token"]


@pytest.fixture(scope="module")
def hub(tmp_path_factory):
    assert CHP.exists(), "make test installs configurable-http-proxy (the Makefile's $(CHP))"
    tmp = tmp_path_factory.mktemp("hub")
    port = free_port()
    (tmp / "jupyterhub_config.py").write_text(_config(tmp, port))
    env = dict(os.environ, PATH=f"{BIN}:{os.environ.get('PATH', '')}")
    log = open(tmp / "hub.log", "w")  # noqa: SIM115 - the hub's log, closed at teardown
    process = subprocess.Popen(
        [str(BIN / "jupyterhub"), "-f", str(tmp / "jupyterhub_config.py")],
        cwd=tmp,
        env=env,
        stdout=log,
        stderr=subprocess.STDOUT,
        start_new_session=True,  # the hub, its proxy, the students' servers and their labs: one group
    )
    hub = Hub(f"http://127.0.0.1:{port}", process)
    try:
        wait_for(lambda: _answers(f"{hub.url}/hub/api/", process, tmp), timeout=120)
        hub.start_server("ada")
        yield hub
    finally:
        process.send_signal(signal.SIGTERM)  # the hub stops the students' servers (cleanup_servers)
        try:
            process.wait(timeout=60)
        except subprocess.TimeoutExpired:
            pass
        try:
            os.killpg(process.pid, signal.SIGKILL)  # anything the hub left: none is expected
        except ProcessLookupError:
            pass
        process.wait()
        log.close()


def _answers(url: str, process: subprocess.Popen, tmp: Path) -> bool:
    assert process.poll() is None, (tmp / "hub.log").read_text()[-3000:]
    try:
        return http.get(url, timeout=5).status_code == 200
    except httpx.HTTPError:
        return False


def _server_pid(user: str) -> int:
    """The pid of `user`'s Jupyter server (jupyterhub-singleuser, started by the spawner)."""
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            environ = (entry / "environ").read_bytes().split(b"\0")
            cmdline = (entry / "cmdline").read_bytes()
        except OSError:
            continue
        if b"jupyterhub-singleuser" in cmdline and f"JUPYTERHUB_USER={user}".encode() in environ:
            return int(entry.name)
    raise AssertionError(f"no Jupyter server of {user}")


def _environment(pid: int) -> dict[str, str]:
    """The environment a process started with (a student's server: what her terminals inherit)."""
    pairs = Path(f"/proc/{pid}/environ").read_bytes().split(b"\0")
    return dict(p.decode().split("=", 1) for p in pairs if b"=" in p)


def _descendants(pid: int) -> list[int]:
    children = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                parent = int((entry / "stat").read_text().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
            children.setdefault(parent, []).append(int(entry.name))
    found, todo = [], [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            found.append(child)
            todo.append(child)
    return found


def _login(browser, hub: Hub, user: str):
    """A browser session signed in as `user` on the hub's login page."""
    context = browser.new_context(viewport={"width": 1500, "height": 900})
    page = context.new_page()
    page.set_default_timeout(180_000)  # a loaded 2-core machine; the waits end as soon as the page is there
    page.goto(f"{hub.url}/hub/login")
    page.fill("#username_input", user)
    page.fill("#password_input", PASSWORD)
    page.click("#login_submit")
    page.wait_for_url(re.compile(r".*/(user|hub)/.*"))
    return context, page


@pytest.fixture(scope="module")
def browser():
    from playwright.sync_api import sync_playwright

    assert os.path.exists(CHROMIUM), "make test installs Debian's chromium-headless-shell"
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        yield browser
        browser.close()


def test_the_launcher_lists_the_labs(hub):
    """JupyterLab's launcher shows what jupyter-server-proxy lists: hri-lab and hri-lab mobile."""
    token = hub.token("ada")
    answer = http.get(
        f"{hub.url}/user/ada/server-proxy/servers-info", headers={"Authorization": f"token {token}"}, timeout=60
    )
    assert answer.status_code == 200, answer.text
    entries = {s["name"]: s["launcher_entry"] for s in answer.json()["server_processes"]}
    assert entries["hri-lab"]["title"] == "hri-lab"
    assert entries["hri-lab-mobile"]["title"] == "hri-lab mobile"
    assert entries["hri-lab"]["path_info"] == "hri-lab/"


def test_her_lab_live_in_chromium(hub, browser):
    """Signed in as ada, the launcher's URL shows her dashboard updating, its controls work (POSTs
    through the hub, the lab's origin check passed: Start with its force, Stop with no field), and
    the 3D view comes through the same prefix."""
    context, page = _login(browser, hub, "ada")
    try:
        page.goto(f"{hub.url}/user/ada/hri-lab/?view=embed")  # embedded even where WebGL is software
        page.wait_for_function("/t = \\d/.test(document.querySelector('#health').textContent)")
        first = page.locator("#health").inner_text()
        page.wait_for_function("(t) => document.querySelector('#health').textContent !== t", arg=first)
        page.locator("#ctl-start").click()
        page.wait_for_function("document.querySelector('#st-lifting').textContent.startsWith('ON')")
        page.wait_for_function("/ N/.test(document.querySelector('#st-fn').textContent)")  # F_ext's stream
        page.frame_locator("#view").locator(CONTROL_PANEL_TAB).wait_for(state="attached")
        assert page.locator("#view").get_attribute("src").startswith(f"{hub.url}/user/ada/hri-lab/view/3d/")
        page.locator("#ctl-stop").click()  # and stopped: the software-WebGL view then has nothing to redraw
        # Stop sends no fields: a body-less POST through the proxy arrived typed as a form, and the lab
        # refused it (415); the page sends {}
        page.wait_for_function("document.querySelector('#st-lifting').textContent === 'off'")
        message = page.locator("#ctl-message").inner_text()
        assert message.startswith("stop_cooperative_lifting: ") and "not accepted" not in message, message
        page.close()  # before the API's docs load: its streams would go on beside them
        docs = context.new_page()
        docs.goto(f"{hub.url}/user/ada/hri-lab/docs")
        docs.wait_for_selector(".swagger-ui .opblock", timeout=180_000)  # its schema fetched through the prefix
        docs.close()
    finally:
        context.close()


def test_roslibpy_with_her_environment(hub):
    """A roslibpy client with what her terminal has (her server's environment: its prefix and her hub
    token) subscribes to F_ext through the hub."""
    env = _environment(_server_pid("ada"))
    prefix, token = env["JUPYTERHUB_SERVICE_PREFIX"], env["JUPYTERHUB_API_TOKEN"]
    lab = f"{hub.url}{prefix}hri-lab/"
    ros = roslibpy.Ros(
        lab.replace("http://", "ws://"), headers={"Authorization": f"token {token}"}, transport="asyncio"
    )
    ros.run(timeout=60)
    try:
        received = []
        topic = roslibpy.Topic(ros, F_EXT, "geometry_msgs/WrenchStamped")
        topic.subscribe(received.append)
        wait_for(lambda: len(received) >= 3, timeout=60)
        assert set(received[-1]["wrench"]) == {"force", "torque"}
        topic.unsubscribe()
    finally:
        ros.terminate()


def test_her_jupyterlab_terminal_needs_no_flag(hub):
    """In a terminal of her JupyterLab (the terminals API JupyterLab's own uses), `hri-lab topic echo`
    reaches her lab through her server: $HRI_LAB_URL and her hub token come from the server."""
    token = hub.token("ada")
    headers = {"Authorization": f"token {token}"}
    answer = http.post(f"{hub.url}/user/ada/api/terminals", headers=headers, timeout=60)
    assert answer.status_code == 200, answer.text
    name = answer.json()["name"]
    socket = f"{hub.url.replace('http://', 'ws://')}/user/ada/terminals/websocket/{name}"
    # the quotes keep the echoed command line from matching what the command prints
    command = f'echo LA""B=$HRI_LAB_URL; {BIN}/hri-lab topic echo {F_EXT} --count 1; echo EX""IT=$?\r'
    output = ""
    with connect(socket, additional_headers=headers, open_timeout=60) as terminal:
        terminal.send(json.dumps(["stdin", command]))
        end = time.monotonic() + 120
        while "EXIT=" not in output and time.monotonic() < end:
            kind, *data = json.loads(terminal.recv(timeout=120))
            if kind == "stdout":
                output += data[0]
    assert re.search(r"LAB=http://127\.0\.0\.1:\d+/user/ada/hri-lab/", output), output
    assert "EXIT=0" in output, output
    assert "force" in output, output
    http.delete(f"{hub.url}/user/ada/api/terminals/{name}", headers=headers, timeout=60)


def test_another_student_gets_403_everywhere(hub, browser):
    """Bob, signed in, gets a 403 on ada's lab: its page in his browser; its API, rosbridge and the
    3D view's WebSocket with his token. Ada's lab still answers her, and the hub's admin."""
    context, page = _login(browser, hub, "bob")
    try:
        answer = page.goto(f"{hub.url}/user/ada/hri-lab/")
        assert answer is not None
        assert answer.status == 403, answer.status
    finally:
        context.close()
    bob = {"Authorization": f"token {hub.token('bob')}"}
    lab = f"{hub.url}/user/ada/hri-lab"
    for path in ("/", "/health", "/services", "/view"):
        assert http.get(lab + path, headers=bob, timeout=60).status_code == 403, path
    assert http.post(lab + "/services/reset_simulation", headers=bob, json={}, timeout=60).status_code == 403
    for path in ("/", "/view/3d/", f"/topics{F_EXT}/stream"):
        with pytest.raises(websockets.exceptions.InvalidStatus) as refused:
            connect(lab.replace("http://", "ws://") + path, additional_headers=bob, open_timeout=60).close()
        assert refused.value.response.status_code == 403, path
    ada = {"Authorization": f"token {hub.token('ada')}"}
    assert http.get(lab + "/health", headers=ada, timeout=60).json()["loop_alive"]
    instructor = {"Authorization": f"token {hub.token('instructor')}"}  # the hub's admin (docs/hosting.md)
    assert http.get(lab + "/health", headers=instructor, timeout=60).json()["loop_alive"]


def test_the_lab_refuses_what_the_hub_did_not_proxy(hub):
    """Another user of the same machine reaching ada's lab's port directly: 403, page and WebSocket."""
    server = _server_pid("ada")
    ports = set()
    for pid in _descendants(server):
        try:
            cmdline = Path(f"/proc/{pid}/cmdline").read_bytes().split(b"\0")
        except OSError:
            continue
        if b"serve" in cmdline and b"--port" in cmdline:
            ports.add(int(cmdline[cmdline.index(b"--port") + 1]))
    assert ports, "ada's lab runs under her server"
    for port in ports:
        assert http.get(f"http://127.0.0.1:{port}/health", timeout=30).status_code == 403
        with pytest.raises(websockets.exceptions.InvalidStatus):
            connect(f"ws://127.0.0.1:{port}/", open_timeout=30).close()


def test_stopping_her_server_leaves_no_lab(hub):
    """The hub stops ada's server: her lab and everything it started end with it."""
    server = _server_pid("ada")
    labs = [pid for pid in _descendants(server) if b"app.cli" in Path(f"/proc/{pid}/cmdline").read_bytes()]
    assert labs, "ada's lab runs under her server"
    below = {pid for lab in labs for pid in _descendants(lab)} | set(labs)
    answer = hub.api.delete("/users/ada/server")
    assert answer.status_code in (202, 204), answer.text
    wait_for(lambda: not hub.api.get("/users/ada").json()["servers"], timeout=120)
    for pid in below:
        wait_for(lambda pid=pid: process_gone(pid), timeout=60)
