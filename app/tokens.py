"""The lab's access token: what a token must be and how a presented one is checked. Both front
ends (the HTTP API, app/api/access.py, and rosbridge, app/rosbridge/) import it from here."""

from __future__ import annotations

import hmac
import os
from urllib.parse import urlsplit

TOKEN_ENV = "HRI_LAB_TOKEN"
MIN_TOKEN_LENGTH = 16


def token_problem(token: str) -> str | None:
    """Why a token cannot protect a server (None: it can)."""
    if len(token) < MIN_TOKEN_LENGTH:
        return f"the token must have at least {MIN_TOKEN_LENGTH} characters (e.g. `openssl rand -hex 16`)"
    return None


def token_matches(presented: bytes | str, token: str) -> bool:
    """The presented token equals the server's, compared as bytes in constant time."""
    if isinstance(presented, str):
        presented = presented.encode("utf-8", "surrogatepass")
    return hmac.compare_digest(presented, token.encode("utf-8"))


def presented_token(headers: list[tuple[bytes, bytes]]) -> bytes:
    """The token a request carries (`Authorization: Bearer <token>` or `X-HRI-Lab-Token`), as the
    raw header bytes."""
    values = dict(headers)
    auth = values.get(b"authorization", b"")
    if auth[:7].lower() == b"bearer ":
        return auth[7:].strip()
    return values.get(b"x-hri-lab-token", b"").strip()


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
