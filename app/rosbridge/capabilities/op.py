"""One op of the protocol as a capability module declares it."""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from typing import Any

# handler(session, message, id_): session is the client's (app/rosbridge/session.py), message the
# parsed frame, id_ its "id" when that is a string or an integer (else None)
Handler = Callable[[Any, dict, Any], Awaitable[None]]


@dataclass(frozen=True)
class Op:
    handler: Handler
    mutating: bool = False  # with a token set, the client must have presented it
