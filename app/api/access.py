"""Access: the server binds 127.0.0.1 by default. Binding any other address requires a token,
which every state-changing request (POST, PUT, PATCH, DELETE) must carry as
`Authorization: Bearer <token>` (or `X-HRI-Lab-Token: <token>`); reading (GET, topic streams) and
the 3D view stay open, and the view's controls are turned off when a token is set."""
import hmac
import ipaddress
import socket

from starlette.middleware.base import BaseHTTPMiddleware
from starlette.requests import Request
from starlette.responses import JSONResponse, Response

TOKEN_ENV = "HRI_LAB_TOKEN"
MUTATING = {"POST", "PUT", "PATCH", "DELETE"}


def is_loopback(host: str) -> bool:
    """True for 127.0.0.0/8, ::1 and names that resolve only to them (localhost)."""
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        pass
    try:
        addresses = {info[4][0] for info in socket.getaddrinfo(host, None)}
    except OSError:
        return False
    return bool(addresses) and all(ipaddress.ip_address(a.split("%")[0]).is_loopback for a in addresses)


def presented_token(request: Request) -> str:
    auth = request.headers.get("authorization", "")
    if auth.lower().startswith("bearer "):
        return auth[7:].strip()
    return request.headers.get("x-hri-lab-token", "")


class TokenMiddleware(BaseHTTPMiddleware):
    def __init__(self, app, token: str) -> None:
        super().__init__(app)
        self.token = token

    async def dispatch(self, request: Request, call_next) -> Response:
        if request.method in MUTATING and not hmac.compare_digest(presented_token(request), self.token):
            return JSONResponse(
                {"detail": "this server needs a token for changes: send 'Authorization: Bearer <token>'"},
                status_code=401, headers={"WWW-Authenticate": "Bearer"},
            )
        return await call_next(request)
