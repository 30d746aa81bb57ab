"""The lab's access token: what a token must be and how a presented one is checked. Both front
ends (the HTTP API, app/api/access.py, and rosbridge, app/rosbridge/) import it from here, and
the Throttle both slow a wrong token with."""

from __future__ import annotations

import asyncio
import hmac
import time

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


class Throttle:
    """Delay of the answer to a wrong token, per client address: 0.1 s x 2^(failures - 1), at most
    2 s; failures are forgotten `forget_s` seconds after the last one."""

    def __init__(self, first_s: float = 0.1, max_s: float = 2.0, forget_s: float = 60.0, clock=time.monotonic) -> None:
        self.first_s, self.max_s, self.forget_s, self.clock = first_s, max_s, forget_s, clock
        self.failures: dict[str, tuple[int, float]] = {}  # client -> (count, time of the last)
        self.locks: dict[str, asyncio.Lock] = {}

    def fail(self, client: str) -> float:
        """Count a failure; the delay (s) before answering it."""
        now = self.clock()
        count, last = self.failures.get(client, (0, now))
        count = 1 if now - last > self.forget_s else count + 1
        self.failures[client] = (count, now)
        if len(self.failures) > 10_000:  # many addresses: keep the recent ones
            for key in sorted(self.failures, key=lambda k: self.failures[k][1])[:5_000]:
                self.failures.pop(key, None)
                self.locks.pop(key, None)
        return min(self.max_s, self.first_s * 2.0 ** (count - 1))

    def succeed(self, client: str) -> None:
        self.failures.pop(client, None)

    def lock(self, client: str) -> asyncio.Lock:
        return self.locks.setdefault(client, asyncio.Lock())
