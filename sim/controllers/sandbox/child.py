"""What runs inside the jail (started by parent.py through jail.py): limits first, then one
instance of the student's class served over the wire (wire.py). It imports only the wire and the
controller interface: nothing of the parent's side, no robot model.

Before the student's code runs: normal scheduling (never the loop's SCHED_FIFO), resource limits
(memory, CPU time, file size, no real-time priority), one BLAS thread, stdout/stderr discarded.
The student's file arrives as text in the first message: nothing else of the grader's file system
needs to be visible.
    python -m sim.controllers.sandbox.child MEMORY_BYTES CPU_SECONDS CLASS_NAME
"""
from __future__ import annotations

import linecache
import os
import resource
import struct
import sys
import traceback
import types

import numpy as np

from sim.controllers.sandbox import wire


def limit(memory_bytes: int, cpu_seconds: int) -> None:
    try:
        os.sched_setscheduler(0, os.SCHED_OTHER, os.sched_param(0))
    except (OSError, AttributeError):
        pass
    limits = [(resource.RLIMIT_RTPRIO, 0), (resource.RLIMIT_CORE, 0), (resource.RLIMIT_FSIZE, 16 << 20)]
    if memory_bytes > 0:
        limits.append((resource.RLIMIT_AS, memory_bytes))
    if cpu_seconds > 0:
        limits.append((resource.RLIMIT_CPU, cpu_seconds))
    for which, value in limits:
        resource.setrlimit(which, (value, value))
    try:  # die with the parent also without bwrap (--unsandboxed): prctl(PR_SET_PDEATHSIG, SIGKILL)
        import ctypes

        ctypes.CDLL(None).prctl(1, 9)
    except (OSError, AttributeError):
        pass
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 1)
    os.dup2(null, 2)


class ChildEnd:
    """Serves one instance of the student's class over two pipes."""

    def __init__(self, read_fd: int, write_fd: int) -> None:
        self.read_fd, self.write_fd = read_fd, write_fd
        self._inbox = b""  # bytes read from the parent, not yet used

    def _receive(self) -> tuple[bytes, bytes] | None:
        header = self._exact(wire.HEADER.size)
        if header is None:
            return None
        op, size = wire.HEADER.unpack(header)
        return op, self._exact(size) or b""

    def _exact(self, size: int) -> bytes | None:
        """`size` bytes (a whole request usually arrives in one read); None at the end of input."""
        while len(self._inbox) < size:
            chunk = os.read(self.read_fd, wire.READ_CHUNK)
            if not chunk:
                return None
            self._inbox += chunk
        data, self._inbox = self._inbox[:size], self._inbox[size:]
        return data

    def _send(self, kind: bytes, payload: bytes) -> None:
        wire.write_all(self.write_fd, wire.HEADER.pack(kind, len(payload)) + payload)

    def _error(self, what: str, exc: BaseException) -> None:
        trace = "".join(traceback.format_exception(exc))
        self._send(b"e", f"raised {type(exc).__name__}: {exc}\n{trace}"[:wire.MAX_TEXT].encode("utf-8", errors="replace"))

    def serve(self, class_name: str) -> int:
        message = self._receive()
        if message is None:
            return 0
        filename, _, source = message[1].partition(b"\0")
        try:
            instance = self._load(filename.decode(), source.decode("utf-8", errors="replace"), class_name)
        except BaseException as exc:  # noqa: BLE001 - even sys.exit() at import is a load error
            if isinstance(exc, LookupError):
                self._send(b"e", str(exc.args[0]).encode())
            else:
                self._send(b"e", f"importing {filename.decode()} failed: {type(exc).__name__}: {exc}".encode())
            return 1
        has = [callable(getattr(instance, name, None)) for name in ("start", "stop")]
        self._send(b"k", bytes(has))
        while (message := self._receive()) is not None:
            op, payload = message
            try:
                self._send(*self._handle(instance, op, payload))
            except BaseException as exc:  # noqa: BLE001 - reported; the parent decides
                self._error(op.decode(), exc)
        return 0

    @staticmethod
    def _load(filename: str, source: str, class_name: str):
        module = types.ModuleType("cooperative_lifting")
        module.__file__ = filename
        sys.modules[module.__name__] = module
        linecache.cache[filename] = (len(source), None, source.splitlines(True), filename)
        exec(compile(source, filename, "exec"), module.__dict__)  # noqa: S102 - the sandbox is the point
        cls = getattr(module, class_name, None)
        if not isinstance(cls, type):
            raise LookupError(f"{filename} has no class {class_name} (give another with {filename}:ClassName)")
        for method in ("reset", "step"):
            if not callable(getattr(cls, method, None)):
                raise LookupError(f"{class_name} in {filename} has no {method}() method")
        return cls()

    @staticmethod
    def _handle(instance, op: bytes, payload: bytes) -> tuple[bytes, bytes]:
        if op == b"R":
            instance.reset()
            return b"k", b""
        values = struct.unpack(f"<{len(payload) // 8}d", payload)
        if op == b"S":
            wrench, transform = np.array(values[:6]), np.array(values[6:22]).reshape(4, 4)
            params = wire.params_from_floats(values[22:-1])
            raw = instance.step(wrench, transform, params, values[-1])
            try:
                twist = np.asarray(raw, dtype=np.float64)
            except (TypeError, ValueError):
                raise TypeError(f"step returned {type(raw).__name__}, not 6 numbers") from None
            if twist.shape != (6,):
                raise ValueError(f"step returned shape {twist.shape}, expected (6,) = [vx, vy, vz, wx, wy, wz]")
            return b"k", twist.tobytes()
        params = wire.params_from_floats(values[:len(wire.PARAM_FIELDS)])
        message = instance.start(params, float(values[-1])) if op == b"A" else instance.stop(params)
        return b"p", np.asarray(wire.params_to_floats(params), float).tobytes() + str(message)[:wire.MAX_TEXT].encode("utf-8", "replace")


def main(argv: list[str]) -> int:
    memory_bytes, cpu_seconds, class_name = int(argv[0]), int(argv[1]), argv[2]
    limit(memory_bytes, cpu_seconds)
    return ChildEnd(wire.REQUEST_FD, wire.ANSWER_FD).serve(class_name)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
