"""The 3D view through the lab's own port, at /view/3d/: its page (viser's one-file client) and its
WebSocket relayed to the viser server's port. Behind a JupyterHub only the lab's port is proxied
(jupyter-server-proxy proxies one port per server), so the page embeds the view from here; on a
laptop the page embeds the viser server directly (app/api/system.py's /view says which).

The relay adds the proxy's secret (app/security.py) when the lab has one: the viser server then
answers nothing else. Frames pass as they come, each way; either side closing closes the other."""

from __future__ import annotations

import asyncio
from urllib.parse import urlsplit

import websockets
from fastapi import APIRouter, Request, WebSocket, WebSocketDisconnect
from fastapi.responses import Response

from app.security import PROXY_HEADER, proxy_secret

PATH = "/view/3d/"
MAX_FRAME = 50 * 1024 * 1024  # bytes: viser's own limit on its server's messages

router = APIRouter(include_in_schema=False)


def _view_address(state) -> tuple[str, int] | None:
    view = getattr(state, "view", None)
    if view is None:
        return None
    parts = urlsplit(view.url)
    return parts.hostname or "127.0.0.1", parts.port or 80


def _headers() -> dict[str, str]:
    secret = proxy_secret()
    return {PROXY_HEADER: secret} if secret else {}


@router.get(PATH)
async def view_page(request: Request) -> Response:
    """viser's client page, fetched from the view's server."""
    address = _view_address(request.app.state)
    if address is None:
        return Response('{"detail": "the 3D view is off"}', status_code=404, media_type="application/json")
    host, port = address
    import httpx  # here, not at the server's start (its import is ~0.3 s of CPU; most labs never relay the view)

    async with httpx.AsyncClient(timeout=10.0) as client:
        answer = await client.get(f"http://{host}:{port}/", headers={**_headers(), "Accept-Encoding": "identity"})
    return Response(answer.content, status_code=answer.status_code, media_type=answer.headers.get("content-type"))


@router.websocket(PATH.rstrip("/"))  # viser's client opens its socket at its page's path less the last slash
@router.websocket(PATH)
async def view_socket(socket: WebSocket) -> None:
    """The page's WebSocket to the viser server, relayed frame by frame."""
    address = _view_address(socket.app.state)
    if address is None:
        await socket.close(code=1011, reason="the 3D view is off")
        return
    host, port = address
    offered = [p.strip() for p in socket.headers.get("sec-websocket-protocol", "").split(",") if p.strip()]
    try:
        upstream = await websockets.connect(
            f"ws://{host}:{port}/",
            additional_headers=_headers(),
            subprotocols=offered or None,  # type: ignore[arg-type]  # viser's "viser-v..." protocol names
            max_size=MAX_FRAME,
            compression=None,
        )
    except (OSError, websockets.InvalidHandshake) as exc:
        await socket.close(code=1011, reason=f"the 3D view cannot be reached: {exc}"[:120])
        return
    await socket.accept(subprotocol=upstream.subprotocol)

    async def down() -> None:  # viser -> the page
        async for frame in upstream:
            if isinstance(frame, bytes):
                await socket.send_bytes(frame)
            else:
                await socket.send_text(frame)

    async def up() -> None:  # the page -> viser
        while True:
            message = await socket.receive()
            if message["type"] == "websocket.disconnect":
                return
            data = message.get("bytes")
            await upstream.send(data if data is not None else message.get("text", ""))

    tasks = [asyncio.ensure_future(down()), asyncio.ensure_future(up())]
    try:
        await asyncio.wait(tasks, return_when=asyncio.FIRST_COMPLETED)
    except WebSocketDisconnect:
        pass
    finally:
        for task in tasks:
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)
        await upstream.close()
        try:
            await socket.close()
        except RuntimeError:  # already closed by the page
            pass
