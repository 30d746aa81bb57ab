"""Cross-site requests are refused (app/security.py): Host, Origin/Referer, content types,
WebSocket upgrades (API and 3D view); the lab's own page, the CLI and curl-like clients work."""

import pytest
import viser
from starlette.websockets import WebSocketDisconnect
from websockets.exceptions import InvalidStatus
from websockets.sync.client import connect

from app.view.scene import guarded_websocket_server
from tests.http_client import http

EVIL = {"origin": "http://evil.example"}


def speed(client) -> float:
    return client.get("/params/keytwist/linear_speed").json()["value"]


def test_host_must_name_this_server(client):
    """DNS rebinding: a foreign name pointing at the server is refused, reading included."""
    for host in ("evil.example", "evil.example:80", "localhost:81", "127.0.0.1.evil.example"):
        response = client.get("/services", headers={"host": host})
        assert response.status_code == 403 and "Host" in response.json()["detail"], host
    for host in ("testserver", "localhost", "127.0.0.1:80", "[::1]"):
        assert client.get("/services", headers={"host": host}).status_code == 200, host


def test_a_foreign_origin_cannot_change_anything(client):
    before = speed(client)
    dump = f"keytwist:\n  ros__parameters:\n    linear_speed: {before / 2}\n"
    # the repro: a text/plain POST from another site
    r = client.post("/params/load", content=dump, headers={**EVIL, "content-type": "text/plain"})
    assert r.status_code == 403
    assert "evil.example" in r.json()["detail"]
    for path in ("/services/reset_simulation", "/services/stop_cooperative_lifting"):  # body-less
        assert client.post(path, headers=EVIL).status_code == 403
    assert client.put("/params/keytwist/linear_speed", json={"value": 0.05}, headers=EVIL).status_code == 403
    assert client.post("/services/reset_simulation", headers={"referer": "http://evil.example/page"}).status_code == 403
    assert client.post("/services/reset_simulation", headers={"origin": "null"}).status_code == 403
    assert speed(client) == before
    # the lab's own page (same origin), and clients that send no Origin, go through
    assert client.post(
        "/services/add_two_ints", json={"a": 1, "b": 2}, headers={"origin": "http://testserver"}
    ).json() == {"sum": 3}
    assert client.post("/services/stop_cooperative_lifting").status_code == 200


def test_mutating_endpoints_accept_only_their_content_types(client):
    before = speed(client)
    dump = f"keytwist:\n  ros__parameters:\n    linear_speed: {before / 2}\n"
    for content_type in ("text/plain", "application/x-www-form-urlencoded", "multipart/form-data; boundary=x", None):
        headers = {"content-type": content_type} if content_type else {}
        r = client.post("/params/load", content=dump.encode(), headers=headers)
        assert r.status_code == 415 and "application/yaml" in r.json()["detail"], content_type
    r = client.post("/services/add_two_ints", content=b'{"a": 1, "b": 2}', headers={"content-type": "text/plain"})
    assert r.status_code == 415
    assert "application/json" in r.json()["detail"]
    assert speed(client) == before
    ok = client.post("/params/load", content=dump.encode(), headers={"content-type": "application/yaml"})
    assert ok.status_code == 200
    assert ok.json()["successful"]
    assert speed(client) == before / 2
    client.put("/params/keytwist/linear_speed", json={"value": before})


def test_websocket_upgrades_check_the_origin(client):
    path = "/topics/joint_states/stream?rate=50"
    with pytest.raises(WebSocketDisconnect), client.websocket_connect(path, headers=EVIL) as ws:
        ws.receive_json()
    with pytest.raises(WebSocketDisconnect), client.websocket_connect(path, headers={"host": "evil.example"}) as ws:
        ws.receive_json()
    for headers in ({}, {"origin": "http://testserver"}):  # roslibpy-like (no Origin), the page
        with client.websocket_connect(path, headers=headers) as ws:
            assert "position" in ws.receive_json()


def test_the_3d_view_refuses_a_foreign_origin():
    """viser's own server, started the way the lab starts it: a forged gizmo message from another
    site never arrives because the upgrade is refused."""
    with guarded_websocket_server("127.0.0.1"):
        server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    port = server.get_port()
    protocol = [f"viser-v{viser.__version__}"]
    try:
        with pytest.raises(InvalidStatus) as refused:
            connect(f"ws://127.0.0.1:{port}", origin="http://evil.example", subprotocols=protocol)
        assert refused.value.response.status_code == 403
        assert http.get(f"http://127.0.0.1:{port}/", headers={"host": "evil.example"}).status_code == 403
        for origin in (None, f"http://127.0.0.1:{port}"):
            with connect(f"ws://127.0.0.1:{port}", origin=origin, subprotocols=protocol):
                pass
        assert http.get(f"http://127.0.0.1:{port}/").status_code == 200
    finally:
        server.stop()
