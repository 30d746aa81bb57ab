"""The ops of rosbridge v2 by name: each capability module's OPS, gathered once (an op declared
twice is a bug found at import)."""

from __future__ import annotations

from app.rosbridge.capabilities import (
    actions,
    advertise,
    advertise_action,
    advertise_service,
    call_service,
    connection,
    node,
    publish,
    service_response,
    subscribe,
)
from app.rosbridge.capabilities.op import Op

MODULES = (
    connection,
    node,
    subscribe,
    advertise,
    publish,
    call_service,
    advertise_service,
    service_response,
    actions,
    advertise_action,
)


def _gather() -> dict[str, Op]:
    ops: dict[str, Op] = {}
    for module in MODULES:
        for name, op in module.OPS.items():
            if name in ops:
                raise ValueError(f"rosbridge op '{name}' declared twice ({module.__name__})")
            ops[name] = op
    return ops


OPS = _gather()
