"""The ops of rosbridge v2 by name: each capability module's OPS, gathered once (an op declared
twice is a bug found at import), and the capabilities a session makes one of for its client."""

from __future__ import annotations

from app.rosbridge.capabilities import (
    actions,
    advertise,
    advertise_action,
    advertise_service,
    call_service,
    connection,
    endpoints,
    node,
    publish,
    service_response,
    subscribe,
)
from app.rosbridge.capabilities.capability import Capability, Ops

MODULES = (
    connection,
    node,
    endpoints,
    subscribe,
    advertise,
    publish,
    call_service,
    advertise_service,
    service_response,
    actions,
    advertise_action,
)


def _gather() -> Ops:
    ops: Ops = {}
    for module in MODULES:
        for name, op in module.OPS.items():
            if name in ops:
                raise ValueError(f"rosbridge op '{name}' declared twice ({module.__name__})")
            ops[name] = op
    return ops


OPS = _gather()
# one object of each per client, made in this order and finished in it (app/rosbridge/session.py)
CAPABILITIES: tuple[type[Capability], ...] = tuple(dict.fromkeys(op.capability for op in OPS.values()))
