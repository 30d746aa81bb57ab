"""The messages between the parent (parent.py) and the child (child.py): what crosses the boundary.

The parent sends only what the real robot gives a controller and reads back 6 numbers; it never
unpickles anything from the child. Messages: a header `<cI` (opcode, payload bytes), then the payload:
    parent -> child  L load   filename NUL source (utf-8)
                     R reset  -
                     S step   float64[6 wrench_ee, 16 transform_ee_to_base (row-major), P params, dt]
                     A start  float64[P params, force]      O stop  float64[P params]
    child -> parent  k ok     step: float64[6 twist_base]; load: 2 bytes (has start, has stop)
                     p params float64[P params] + the service's message (utf-8)
                     e error  the reason, with the traceback (utf-8)
P = the fields of LiftingParams in declaration order (`running` as 0/1).
The child reads on fd 3 and answers on fd 4.
"""
from __future__ import annotations

import dataclasses
import os
import struct

from sim.controllers.interface import LiftingParams

REQUEST_FD, ANSWER_FD = 3, 4  # the child's ends of the two pipes
HEADER = struct.Struct("<cI")
PARAM_FIELDS = tuple(f.name for f in dataclasses.fields(LiftingParams))
STEP_FLOATS = 6 + 16 + len(PARAM_FIELDS) + 1
STEP = struct.Struct(f"<cI{STEP_FLOATS}d")  # a whole step request, header included
TWIST = struct.Struct("<6d")
READ_CHUNK = 1 << 16  # bytes asked of a pipe per read (a whole answer arrives in one)
MAX_REPLY = 64 << 10  # bytes; a longer answer is a fault
MAX_TEXT = 4000  # characters of an error or message kept


def params_to_floats(params: LiftingParams) -> list[float]:
    return [float(getattr(params, name)) for name in PARAM_FIELDS]


def params_from_floats(values) -> LiftingParams:
    """LiftingParams from its fields' numbers (PARAM_FIELDS: the dataclass's order; `running` as 0/1)."""
    params = LiftingParams(*map(float, values))
    params.running = bool(params.running)
    return params


def text(payload: bytes) -> str:
    return payload.decode("utf-8", errors="replace")[:MAX_TEXT]


def write_all(fd: int, data: bytes) -> None:
    view = memoryview(data)
    while view:
        view = view[os.write(fd, view):]
