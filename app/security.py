"""Cross-site protection and the request-body limit: one ASGI middleware around every route, HTTP
and WebSocket, present or future (services, parameters, topic and action streams, rosbridge), and
the same checks for the 3D views' servers. Below both front ends that serve a browser (app/api and
app/view import it; it imports neither), beside the access token's rules (app/tokens.py).

A page on another site the student has open must not drive the lab, token or not:
- Host must name this server: the address it was started on, its localhost forms (localhost,
  127.0.0.1, [::1]) or the address the connection came in on, with the server's port; anything
  else (a foreign name re-bound to 127.0.0.1: DNS rebinding) is a 403.
- A state-changing request (POST, PUT, PATCH, DELETE) and a WebSocket upgrade carry no Origin
  (curl, the CLI, roslibpy-style clients) or this server's own origin; a foreign Origin (or, without
  Origin, a foreign Referer) is a 403.
- A state-changing request that has a body or names a content type must be `application/json`
  (`/params/load`: `application/yaml`); anything else is a 415, so a cross-site "simple" request
  (text/plain, a form) never reaches a route.
- A body is at most MAX_BODY_BYTES (1 MiB); a larger one is a 413.

`host_refusal` and `origin_refusal` are the same checks for servers that are not ASGI apps (the 3D
views' viser servers: app/view/scene.py's `guarded_websocket_server`).

Behind a JupyterHub (app/jupyter_proxy.py: the lab started by jupyter-server-proxy in a student's
server), the lab is started with a secret in $HRI_LAB_PROXY_SECRET that the student's server adds to
every request it proxies (PROXY_HEADER), after the hub authenticated the student: then a request
without it is a 403 (another local user, or a page, reaching the lab's port directly), and one with it
names the hub in its Host (not checked: the proxy checked it) while its Origin, when sent, must still
be the page's own (the hub's).
"""

from __future__ import annotations

import hmac
import ipaddress
import json
import os
import socket
from urllib.parse import urlsplit

from starlette.exceptions import HTTPException

MUTATING = {"POST", "PUT", "PATCH", "DELETE"}
MAX_BODY_BYTES = 1 << 20  # 1 MiB
JSON_TYPES = ("application/json",)
YAML_TYPES = ("application/yaml", "application/x-yaml", "text/yaml")
BODY_TYPES = {"/params/load": YAML_TYPES}  # path -> accepted content types (default: JSON_TYPES)
LOCAL_NAMES = ("localhost", "127.0.0.1", "::1")
PROXY_SECRET_ENV = "HRI_LAB_PROXY_SECRET"  # set by app/jupyter_proxy.py for the lab it starts
PROXY_HEADER = "x-hri-lab-proxy"  # the secret, added by the student's Jupyter server to what it proxies


class BodyTooLarge(HTTPException):
    def __init__(self) -> None:
        super().__init__(413, f"the request body is larger than {MAX_BODY_BYTES} bytes")


def split_authority(authority: str) -> tuple[str, int | None] | None:
    """'host[:port]' (IPv6 in brackets) -> (lower-case host without brackets, port or None);
    None when it is not an authority."""
    try:
        parts = urlsplit("//" + authority)
        host, port = parts.hostname, parts.port
    except ValueError:
        return None
    if not host or parts.username is not None or parts.path or parts.query or parts.fragment:
        return None
    return host.lower().rstrip("."), port


def local_names(bound_host: str) -> set[str]:
    """The names a request may use for a server bound to `bound_host`: localhost forms, the bound
    address and, on a non-loopback address, this machine's names."""
    names = set(LOCAL_NAMES) | {bound_host.lower().strip("[]")}
    try:
        loopback = ipaddress.ip_address(bound_host.strip("[]")).is_loopback
    except ValueError:
        loopback = bound_host.lower() == "localhost"
    if not loopback:
        names |= {socket.gethostname().lower(), socket.getfqdn().lower()}
    return names


def host_refusal(host_header: str | None, names: set[str], server: tuple[str, int] | None, scheme: str) -> str | None:
    """Why the Host header does not name this server (None: it does). server = the (address, port)
    the connection came in on."""
    default_port = 443 if scheme in ("https", "wss") else 80
    authority = split_authority(host_header or "")
    if authority is None:
        return "the Host header is missing or malformed"
    host, port = authority
    server_host, server_port = (server[0].lower(), server[1]) if server else (None, None)
    if host not in names and host != server_host:
        return f"Host '{_short(host_header or '')}' is not this server (a foreign name pointing at it is refused)"
    if server_port is not None and (port or default_port) != server_port:
        return f"Host '{_short(host_header or '')}' names another port"
    return None


def origin_refusal(origin: str | None, referer: str | None, host_header: str | None) -> str | None:
    """Why a request from a browser page is not from this server's own page (None: it is, or it
    comes from no page at all: no Origin and no Referer)."""
    source = origin if origin is not None else referer
    if source is None:
        return None
    own = split_authority(host_header or "")
    try:
        parts = urlsplit(source)
        theirs = (parts.hostname or "", parts.port or (443 if parts.scheme == "https" else 80))
    except ValueError:
        theirs = None
    if own is not None and theirs is not None and parts.scheme in ("http", "https"):
        own_port = own[1] or (443 if parts.scheme == "https" else 80)
        if (theirs[0].lower(), theirs[1]) == (own[0], own_port):
            return None
    kind = "Origin" if origin is not None else "Referer"
    return f"cross-site request refused: {kind} '{_short(source)}' is not this server's page"


def content_type_refusal(path: str, content_type: str | None, has_body: bool) -> str | None:
    """Why a state-changing request's body type is not the endpoint's (None: it is)."""
    if content_type is None and not has_body:
        return None
    accepted = BODY_TYPES.get(path, JSON_TYPES)
    media = (content_type or "").split(";", 1)[0].strip().lower()
    if media in accepted:
        return None
    return f"content type '{_short(media) or '(none)'}' is not accepted here; send {' or '.join(accepted)}"


def _short(text: str, limit: int = 80) -> str:
    """At most `limit` characters of an echoed input, printable and encodable."""
    text = text.encode("utf-8", "backslashreplace").decode("utf-8")
    return text if len(text) <= limit else text[:limit] + "..."


def proxy_secret() -> str | None:
    """The secret of the Jupyter server that started this lab (None: not started behind one)."""
    return os.environ.get(PROXY_SECRET_ENV) or None


def proxy_refusal(presented: str | None, secret: str) -> str | None:
    """Why a request did not come through the student's Jupyter server (None: it did)."""
    if presented is not None and hmac.compare_digest(presented.encode("utf-8", "surrogateescape"), secret.encode()):
        return None
    return "this lab answers only through its owner's Jupyter server (JupyterHub): open it from there"


class SiteGuard:
    """The ASGI middleware (see the module's docstring). bound_host: the address the server was
    started on."""

    def __init__(self, app, bound_host: str = "127.0.0.1", secret: str | None = None) -> None:
        self.app = app
        self.names = local_names(bound_host)
        self.secret = secret if secret is not None else proxy_secret()

    async def __call__(self, scope, receive, send) -> None:
        if scope["type"] not in ("http", "websocket"):
            return await self.app(scope, receive, send)
        headers: dict[str, str] = {}
        for key, value in scope["headers"]:
            headers.setdefault(key.decode("latin-1"), value.decode("latin-1"))
        host = headers.get("host")
        if self.secret:  # behind the hub: only what the student's server proxied, naming the hub
            refusal = proxy_refusal(headers.get(PROXY_HEADER), self.secret)
        else:
            refusal = host_refusal(host, self.names, scope.get("server"), scope.get("scheme", "http"))
        if refusal is None and (scope["type"] == "websocket" or scope["method"] in MUTATING):
            refusal = origin_refusal(headers.get("origin"), headers.get("referer"), host)
        if refusal is not None:
            return await _refuse(scope, send, 403, refusal)
        if scope["type"] == "websocket" or scope["method"] not in MUTATING:
            return await self.app(scope, receive, send)

        length = headers.get("content-length")
        has_body = (length not in (None, "0")) or "transfer-encoding" in headers
        refusal = content_type_refusal(scope["path"], headers.get("content-type"), has_body)
        if refusal is not None:
            return await _refuse(scope, send, 415, refusal)
        if length is not None and (not length.isdigit() or int(length) > MAX_BODY_BYTES):
            return await _refuse(scope, send, 413, BodyTooLarge().detail)
        await self.app(scope, _limited(receive), send)


def _limited(receive):
    """receive() that raises BodyTooLarge (a 413) once the body passes MAX_BODY_BYTES."""
    seen = 0

    async def limited():
        nonlocal seen
        message = await receive()
        if message["type"] == "http.request":
            seen += len(message.get("body", b""))
            if seen > MAX_BODY_BYTES:
                raise BodyTooLarge()
        return message

    return limited


async def _refuse(scope, send, status: int, detail: str) -> None:
    if scope["type"] == "websocket":  # closing before accepting: the handshake fails with 403
        await send({"type": "websocket.close", "code": 1008, "reason": detail[:120]})
        return
    body = json.dumps({"detail": detail}).encode()
    await send(
        {
            "type": "http.response.start",
            "status": status,
            "headers": [
                (b"content-type", b"application/json"),
                (b"content-length", str(len(body)).encode()),
                (b"connection", b"close"),
            ],
        }
    )
    await send({"type": "http.response.body", "body": body})
