"""The lab inside a student's Jupyter server: jupyter-server-proxy's entry points (pyproject's
`jupyter_serverproxy_servers`). Wherever hri-lab is installed beside JupyterLab and
jupyter-server-proxy, the launcher shows "hri-lab" and "hri-lab mobile"; a click starts the lab
(`hri-lab serve` on a free port, in the student's server, as the student) and opens it at
`/user/NAME/hri-lab/`. docs/hosting.md is the instructor's side.

Only the student gets in: the hub authenticates every request (HTTP and WebSocket) before the student's
server proxies it, and the lab answers only what that server proxied. A secret drawn when the server
starts is given to the lab ($HRI_LAB_PROXY_SECRET) and added by the server to every request it proxies
(app/security.py's PROXY_HEADER), so another user on the same machine reaching the lab's port directly
gets a 403 too.

The student's terminal reaches the lab with no flag: the server's environment, which JupyterLab's
terminals inherit, gets $HRI_LAB_URL (the lab through the student's own server, which starts it if it
is not running) when the hub named that server ($JUPYTERHUB_SERVICE_URL); the clients add the
student's hub token ($JUPYTERHUB_API_TOKEN) to what they send there (rosclient/headers.py's `lab_headers`)."""

from __future__ import annotations

import os
import secrets
import sys
from pathlib import Path

from app.cli.arguments import URL_ENV
from app.security import PROXY_HEADER, PROXY_SECRET_ENV

ICON = Path(__file__).resolve().parents[1] / "static" / "favicon.svg"
VIEW_ENV = "HRI_LAB_VIEW"  # the 3D view's meshes, set in the students' environment: full (default), light, none
START_TIMEOUT_S = 120  # a first start on a busy node loads the compiled kernels and the meshes
_SECRET = secrets.token_urlsafe(32)  # one per Jupyter server: the processes it starts and the headers it adds


def _server(name: str, title: str, world: str) -> dict:
    """jupyter-server-proxy's dict for one lab: `hri-lab serve` on {port}, prefix stripped (the lab's
    pages use relative URLs), the proxy's secret in its environment and in every proxied request."""
    return {
        "command": [sys.executable, "-m", "app.cli", "serve", "--port", "{port}", "--world", world]
        + ["--view", os.environ.get(VIEW_ENV, "full")],
        "environment": {PROXY_SECRET_ENV: _SECRET},
        "request_headers_override": {PROXY_HEADER: _SECRET},
        "absolute_url": False,
        "timeout": START_TIMEOUT_S,
        "new_browser_tab": True,
        "launcher_entry": {"enabled": True, "title": title, "icon_path": str(ICON), "path_info": f"{name}/"},
    }


def _announce(name: str) -> None:
    """$HRI_LAB_URL for the terminals the student's server starts: the lab through that server."""
    service_url = os.environ.get("JUPYTERHUB_SERVICE_URL")
    if service_url and URL_ENV not in os.environ:
        os.environ[URL_ENV] = service_url.rstrip("/") + f"/{name}/"


def lab() -> dict:
    """The lifting lab, at /user/NAME/hri-lab/."""
    _announce("hri-lab")
    return _server("hri-lab", "hri-lab", "lifting")


def mobile() -> dict:
    """The mobile world, at /user/NAME/hri-lab-mobile/ (its terminal: HRI_LAB_URL=...hri-lab-mobile/)."""
    return _server("hri-lab-mobile", "hri-lab mobile", "mobile")
