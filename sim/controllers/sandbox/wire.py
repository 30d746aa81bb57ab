"""What crosses the boundary between the parent (parent.py) and the child (child.py).

One shared-memory slot (a sealed memfd: no path, its size fixed) holds the current request and
its answer; one byte through a pipe wakes the other side: the parent writes a request and wakes
the child, then blocks until the child has written the answer and woken it. Pipes, not eventfds:
each end of a pipe belongs to one side, so the child cannot steal its parent's wake-up or make its
parent's end block (an eventfd is one file both would share). The parent never unpickles anything
from the child, copies an answer out of the slot before it checks it, and matches its sequence
number (a stray byte or a stale answer is never taken for the answer).

The slot:
    offset 0        request header  `<QcI`  (sequence number, opcode, payload bytes)
    offset 64       answer header   `<QcI`  (the request's sequence number, kind, payload bytes)
    offset 4096     request payload (at most `capacity` bytes)
    then            answer payload  (at most MAX_REPLY bytes)
Requests (parent -> child), and their payloads:
    L load   filename NUL source (utf-8)
    R reset  -
    S step   float64[6 wrench_ee, 16 transform_ee_to_base (row-major), P params, dt]
    A start  float64[P params, force]      O stop  float64[P params]
Answers (child -> parent):
    k ok     step: float64[6 twist_base]; load: 2 bytes (has start, has stop)
    p params float64[P params] + the service's message (utf-8)
    e error  the reason, with the traceback (utf-8)
P = the fields of LiftingParams in declaration order (`running` as 0/1).
The child finds the slot on fd SLOT_FD, its wake-up on WAKE_CHILD_FD (the end of input: the
parent is done), and wakes the parent on WAKE_PARENT_FD (its end: the parent sees the child gone).
"""

from __future__ import annotations

import dataclasses
import mmap
import operator
import os
import struct
from typing import Any

import numpy as np

from sim.controllers.interface import LiftingParams

WAKE_CHILD_FD, WAKE_PARENT_FD, SLOT_FD = 3, 4, 5  # the child's descriptors
HEADER = struct.Struct("<QcI")  # sequence number, opcode or kind, payload bytes
REQUEST_AT, ANSWER_AT, PAYLOAD_AT = 0, 64, 4096
PARAM_FIELDS = tuple(f.name for f in dataclasses.fields(LiftingParams))
STEP_FLOATS = 6 + 16 + len(PARAM_FIELDS) + 1
TWIST_BYTES = 6 * 8
MIN_CAPACITY = 64 << 10  # bytes of request payload at least (a load carries the whole file)
MAX_REPLY = 64 << 10  # bytes; a longer answer is a fault
MAX_TEXT = 4000  # characters of an error or message kept


def slot_bytes(payload: int) -> int:
    """The slot's size for requests of up to `payload` bytes (whole pages)."""
    capacity = -(-max(payload, MIN_CAPACITY) // 4096) * 4096
    return PAYLOAD_AT + capacity + MAX_REPLY


class Slot:
    """The shared region seen through one end: headers, payloads and the step's float views."""

    def __init__(self, fd: int) -> None:
        size = os.fstat(fd).st_size
        self.capacity = size - PAYLOAD_AT - MAX_REPLY
        self.memory = mmap.mmap(fd, size)
        self.answer_at = PAYLOAD_AT + self.capacity
        everything = np.frombuffer(self.memory, dtype=np.float64)
        self.step_in = everything[PAYLOAD_AT // 8 : PAYLOAD_AT // 8 + STEP_FLOATS]  # the step's request
        self.twist_out = everything[self.answer_at // 8 : self.answer_at // 8 + 6]  # the step's answer

    def put_request(self, seq: int, op: bytes, payload: bytes = b"") -> None:
        self.memory[PAYLOAD_AT : PAYLOAD_AT + len(payload)] = payload
        HEADER.pack_into(self.memory, REQUEST_AT, seq, op, len(payload))

    def request(self) -> tuple[int, bytes, int]:
        """(sequence number, opcode, payload bytes) of the request in the slot."""
        return HEADER.unpack_from(self.memory, REQUEST_AT)

    def request_payload(self, size: int) -> bytes:
        return self.memory[PAYLOAD_AT : PAYLOAD_AT + min(max(size, 0), self.capacity)]

    def put_answer(self, seq: int, kind: bytes, payload: bytes = b"") -> None:
        payload = payload[:MAX_REPLY]
        self.memory[self.answer_at : self.answer_at + len(payload)] = payload
        HEADER.pack_into(self.memory, ANSWER_AT, seq, kind, len(payload))

    def answer(self) -> tuple[int, bytes, int]:
        """(sequence number, kind, payload bytes) of the answer in the slot."""
        return HEADER.unpack_from(self.memory, ANSWER_AT)

    def answer_payload(self, size: int) -> bytes:
        return self.memory[self.answer_at : self.answer_at + size]

    def close(self) -> None:
        del self.step_in, self.twist_out  # the views first: an exported buffer keeps the map open
        try:
            self.memory.close()
        except BufferError:  # a view still held somewhere: the map ends with it
            pass


param_values = operator.attrgetter(*PARAM_FIELDS)  # params -> its fields' values in PARAM_FIELDS order (a tuple)


def params_to_floats(params: LiftingParams) -> list[float]:
    return [float(value) for value in param_values(params)]


def params_from_floats(values) -> LiftingParams:
    """LiftingParams from its fields' numbers (PARAM_FIELDS: the dataclass's order; `running` as 0/1)."""
    fields: list[Any] = [float(value) for value in values]
    params = LiftingParams(*fields)
    params.running = bool(params.running)
    return params


def text(payload: bytes) -> str:
    return payload.decode("utf-8", errors="replace")[:MAX_TEXT]
