"""What a client of the lab (a student's program under `hri-lab run`, the `hri-lab` client commands)
sends with its requests: the lab's token, and behind a JupyterHub the student's hub token
(app/jupyter_proxy.py, docs/hosting.md)."""

from __future__ import annotations

import os
from urllib.parse import urlsplit

HUB_TOKEN_ENV, HUB_PREFIX_ENV = "JUPYTERHUB_API_TOKEN", "JUPYTERHUB_SERVICE_PREFIX"


def lab_headers(url: str, token: str | None) -> dict[str, str]:
    """The headers a client sends the lab at `url`: the lab's token, when given, and, for a lab behind
    the student's own Jupyter server (a JupyterHub's: the URL's path under $JUPYTERHUB_SERVICE_PREFIX,
    app/jupyter_proxy.py), the student's hub token, which the hub checks first. The hub reads
    `Authorization`, so the lab's token then goes as `X-HRI-Lab-Token`."""
    headers: dict[str, str] = {}
    hub_token, prefix = os.environ.get(HUB_TOKEN_ENV), os.environ.get(HUB_PREFIX_ENV)
    path = urlsplit(url if "://" in url else "http://" + url).path
    if hub_token and prefix and path.startswith(prefix):
        headers["Authorization"] = f"token {hub_token}"
        if token:
            headers["X-HRI-Lab-Token"] = token
    elif token:
        headers["Authorization"] = f"Bearer {token}"
    return headers
