"""app/security.py: the cross-site checks as functions (Host, Origin/Referer, content types) and the
middleware around a bare ASGI app (no FastAPI): what it refuses never reaches the app, a body past
the limit is a 413 however it arrives. The whole API behind it: tests/app/api/test_cross_site.py."""

import asyncio

import pytest

from app.security import (
    MAX_BODY_BYTES,
    BodyTooLarge,
    SiteGuard,
    content_type_refusal,
    host_refusal,
    local_names,
    origin_refusal,
    split_authority,
)


def test_an_authority_is_a_host_and_a_port():
    assert split_authority("LocalHost:8000") == ("localhost", 8000)
    assert split_authority("[::1]:8080") == ("::1", 8080)
    assert split_authority("example.org.") == ("example.org", None)
    for bad in ("", "user@host:80", "host/path", "host:port", "host?q"):
        assert split_authority(bad) is None, bad


def test_the_names_of_a_loopback_server_are_only_the_local_ones():
    assert local_names("127.0.0.1") == {"localhost", "127.0.0.1", "::1"}
    assert local_names("[::1]") == {"localhost", "127.0.0.1", "::1"}
    assert {"localhost", "10.1.2.3"} <= local_names("10.1.2.3")  # and this machine's names


def test_host_must_name_this_server_and_its_port():
    names = local_names("127.0.0.1")
    server = ("127.0.0.1", 8000)
    assert host_refusal("localhost:8000", names, server, "http") is None
    assert host_refusal("127.0.0.1:8000", names, server, "http") is None
    assert "not this server" in host_refusal("evil.example:8000", names, server, "http")  # DNS rebinding
    assert "another port" in host_refusal("localhost:8001", names, server, "http")
    assert "another port" in host_refusal("localhost", names, server, "http")  # 80 by default
    assert host_refusal("localhost", names, ("127.0.0.1", 80), "http") is None
    assert host_refusal("localhost", names, ("127.0.0.1", 443), "wss") is None
    assert "missing or malformed" in host_refusal(None, names, server, "http")


def test_origin_rules():
    assert origin_refusal(None, None, "127.0.0.1:8000") is None  # no page: curl, the CLI
    assert origin_refusal("http://127.0.0.1:8000", None, "127.0.0.1:8000") is None
    assert origin_refusal("http://localhost:8000", None, "localhost:8000") is None
    assert origin_refusal("http://127.0.0.1:8001", None, "127.0.0.1:8000")  # another local port
    assert origin_refusal(None, "http://evil.example/x", "127.0.0.1:8000")  # Referer when no Origin
    assert origin_refusal("http://[::1", None, "127.0.0.1:8000")  # malformed
    assert origin_refusal("null", None, "127.0.0.1:8000")  # a sandboxed frame, a file: page
    assert "Origin 'http://evil.example'" in origin_refusal("http://evil.example", None, "127.0.0.1:8000")


def test_a_body_must_be_the_endpoints_type():
    assert content_type_refusal("/services/x", None, has_body=False) is None  # a body-less POST
    assert content_type_refusal("/services/x", "application/json; charset=utf-8", True) is None
    assert content_type_refusal("/params/load", "application/yaml", True) is None
    assert "send application/json" in content_type_refusal("/services/x", "text/plain", True)
    assert "application/yaml" in content_type_refusal("/params/load", "application/json", True)
    assert "(none)" in content_type_refusal("/services/x", None, has_body=True)


def call(guard: SiteGuard, scope: dict, body: bytes = b"", chunks: int = 1) -> tuple[list[dict], bool]:
    """The messages the guard sends for one request, and whether the app behind it was reached."""
    reached = []
    size = -(-len(body) // chunks) if body else 0
    parts = [body[i : i + size] for i in range(0, len(body), size)] if body else [b""]
    incoming = [{"type": "http.request", "body": p, "more_body": i < len(parts) - 1} for i, p in enumerate(parts)]
    sent: list[dict] = []

    async def app(scope, receive, send):
        reached.append(True)
        while (await receive()).get("more_body"):
            pass
        await send({"type": "http.response.start", "status": 200, "headers": []})
        await send({"type": "http.response.body", "body": b"ok"})

    async def receive():
        return incoming.pop(0)

    async def send(message):
        sent.append(message)

    guard.app = app
    asyncio.run(guard(scope, receive, send))
    return sent, bool(reached)


def scope(method: str = "POST", kind: str = "http", **headers: str) -> dict:
    return {
        "type": kind,
        "method": method,
        "path": "/services/reset_simulation",
        "scheme": "http",
        "server": ("127.0.0.1", 8000),
        "headers": [
            (k.replace("_", "-").encode(), v.encode()) for k, v in {"host": "127.0.0.1:8000", **headers}.items()
        ],
    }


def test_the_guard_refuses_before_the_app():
    guard = SiteGuard(None)
    sent, reached = call(guard, scope(origin="http://evil.example"))
    assert not reached
    assert sent[0]["status"] == 403
    sent, reached = call(guard, scope(content_type="text/plain", content_length="2"), b"{}")
    assert not reached
    assert sent[0]["status"] == 415
    sent, reached = call(guard, scope(content_type="application/json", content_length=str(MAX_BODY_BYTES + 1)))
    assert not reached
    assert sent[0]["status"] == 413
    sent, reached = call(guard, scope("GET", host="evil.example:8000"))
    assert not reached
    assert sent[0]["status"] == 403
    sent, reached = call(guard, scope("GET", "websocket", origin="http://evil.example"))
    assert not reached
    assert sent == [{"type": "websocket.close", "code": 1008, "reason": sent[0]["reason"]}]
    sent, reached = call(guard, scope(content_type="application/json", content_length="2"), b"{}")
    assert reached
    assert sent[0]["status"] == 200


def test_a_body_sent_in_chunks_is_stopped_at_the_limit():
    """No Content-Length (chunked): the body is counted as it arrives; past the limit, a 413 (raised
    to the app's exception handler, which answers it)."""
    guard = SiteGuard(None)
    with pytest.raises(BodyTooLarge, match=str(MAX_BODY_BYTES)) as refused:
        call(
            guard, scope(content_type="application/json", transfer_encoding="chunked"), b"x" * (MAX_BODY_BYTES + 10), 4
        )
    assert refused.value.status_code == 413
    sent, reached = call(guard, scope(content_type="application/json", transfer_encoding="chunked"), b"x" * 1000, 4)
    assert reached
    assert sent[0]["status"] == 200


def test_behind_a_jupyterhub_only_what_the_students_server_proxied():
    """A lab started by jupyter-server-proxy (app/jupyter_proxy.py) answers only requests carrying its
    server's secret; those name the hub in their Host, and a page's Origin must still be the hub's."""
    guard = SiteGuard(None, secret="s3cret-of-the-server")
    hub = {"host": "hub.example.edu"}
    sent, reached = call(guard, scope("GET", **hub))  # another local user, straight to the port
    assert not reached
    assert sent[0]["status"] == 403
    assert b"Jupyter server" in sent[1]["body"]
    sent, reached = call(guard, scope("GET", "websocket", **hub, x_hri_lab_proxy="a-guess"))
    assert not reached
    assert sent[0]["type"] == "websocket.close"
    proxied = {**hub, "x_hri_lab_proxy": "s3cret-of-the-server"}
    sent, reached = call(guard, scope("GET", **proxied))
    assert reached
    sent, reached = call(guard, scope(**proxied, origin="https://hub.example.edu"))  # the page's POST
    assert reached
    sent, reached = call(guard, scope(**proxied, origin="https://evil.example"))
    assert not reached
    assert sent[0]["status"] == 403
