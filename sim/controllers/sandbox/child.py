"""What runs in a child forked by the jail's zygote (zygote.py, for parent.py): limits first, then
one instance of the student's class served over the wire (wire.py). It imports only the wire and the
controller interface: nothing of the parent's side, no robot model.

Before the student's code runs: normal scheduling (never the loop's SCHED_FIFO), resource limits
(memory, CPU time, file size, open descriptors, no real-time priority), one BLAS thread,
stdout/stderr discarded.
The student's file arrives as text in the first message: nothing else of the grader's file system
needs to be visible.
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


def limit(memory_bytes: int, cpu_seconds: int, file_bytes: int, open_files: int) -> None:
    try:
        os.sched_setscheduler(0, os.SCHED_OTHER, os.sched_param(0))
    except (OSError, AttributeError):
        pass
    # no POSIX message queue: one would outlive the item in its jail's IPC namespace (zygote.py)
    limits = [
        (resource.RLIMIT_RTPRIO, 0),
        (resource.RLIMIT_CORE, 0),
        (resource.RLIMIT_FSIZE, file_bytes),  # a file in /tmp, an anonymous memory file (memfd) too
        (resource.RLIMIT_MSGQUEUE, 0),
        (resource.RLIMIT_NOFILE, open_files),  # files, sockets, pipes, memfds: each memfd at most file_bytes
    ]
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


# The lab's own controllers and their kernels: a file that imports, subclasses or copies them (reads
# their text) is not a submission (docs/sandbox.md, "The lab's reference"): said with its load answer
REFERENCE_MODULES = (
    "sim.controllers.sp",
    "sim.controllers.patch",
    "sim.controllers.lifting_law",
    "sim.controllers.compiled_law",
    "sim.controllers.builtin",
    "sim.compiled_step",
)
MEMORY_SEARCHES = ("gc.get_objects", "gc.get_referrers", "gc.get_referents")  # the lab's objects found in memory


class ReferenceWatch:
    """What the student's code did to reach the lab's reference controllers, from the interpreter's
    audit events (PEP 578: a hook cannot be removed): an import of one of REFERENCE_MODULES, an open
    of one of their files (their source or cached bytecode: an import, or a copy read at run time),
    a search of the process's memory. The zygote imported them: they are forgotten first, so using
    them takes an import. While the file loads a reach is recorded (the grader decides); after it,
    it is refused."""

    def __init__(self) -> None:
        import sim

        self.seen = ""  # the first reach, in words
        self.loading = True
        root = os.path.realpath(os.path.dirname(sim.__file__))
        self.files: dict[tuple[str, str], str] = {}  # (folder, file stem) -> module
        for name in REFERENCE_MODULES:
            *folders, stem = name.split(".")[1:]
            self.files[os.path.join(root, *folders), stem] = name
            self.files[os.path.join(root, *folders, "__pycache__"), stem] = name
            sys.modules.pop(name, None)
            parent = sys.modules.get(name.rpartition(".")[0])
            if parent is not None and hasattr(parent, stem):
                delattr(parent, stem)
        sys.addaudithook(self._hook)

    def _reach(self, event: str, args: tuple) -> str:
        if event == "import" and args and isinstance(args[0], str):
            name = args[0]
            if any(name == m or name.startswith(m + ".") for m in REFERENCE_MODULES):
                return f"imports {name}"
        elif event == "open" and args and isinstance(args[0], (str, bytes)):
            path = os.path.realpath(os.fsdecode(args[0]))
            folder, base = os.path.split(path)
            module = self.files.get((folder, base.split(".")[0]))
            if module is not None:
                return f"reads {path} ({module})"
        elif event in MEMORY_SEARCHES:
            return f"searches the process's memory ({event})"
        return ""

    def _hook(self, event: str, args: tuple) -> None:
        if event not in ("import", "open") and event not in MEMORY_SEARCHES:
            return
        reach = self._reach(event, args)
        if not reach:
            return
        if self.loading:
            self.seen = self.seen or reach
            return
        raise PermissionError(f"the lab's reference controllers are not a submission: your code {reach}")


class ChildEnd:
    """Serves one instance of the student's class through the slot (wire.py)."""

    def __init__(self, wake_fd: int, answer_fd: int, slot_fd: int) -> None:
        self.wake_fd, self.answer_fd = wake_fd, answer_fd
        self.slot = wire.Slot(slot_fd)
        self.seen = 0  # the last request's sequence number
        self.filename = ""  # the student's file, as its code's frames name it

    def _receive(self) -> tuple[int, bytes, int] | None:
        """The next request (sequence number, opcode, payload bytes); None at the end of input."""
        while True:
            if not os.read(self.wake_fd, 64):
                return None
            seq, op, size = self.slot.request()
            if seq != self.seen:
                self.seen = seq
                return seq, op, size

    def _send(self, seq: int, kind: bytes, payload: bytes = b"") -> None:
        self.slot.put_answer(seq, kind, payload)
        os.write(self.answer_fd, b"\1")

    def _error(self, seq: int, exc: BaseException) -> None:
        self._send(
            seq,
            b"e",
            f"raised {type(exc).__name__}: {exc}\n{self._trace(exc)}"[: wire.MAX_TEXT].encode(
                "utf-8", errors="replace"
            ),
        )

    def _trace(self, exc: BaseException) -> str:
        """The traceback of the student's own frames (none of this file's, the grader's): what a
        student can act on. Empty when the student's code is not in it (a wrong return, checked here)."""
        frames = [frame for frame in traceback.extract_tb(exc.__traceback__) if frame.filename == self.filename]
        if not frames:
            return ""
        return "".join(
            [
                "Traceback (most recent call last):\n",
                *traceback.format_list(frames),
                *traceback.format_exception_only(exc),
            ]
        )

    def serve(self, class_name: str) -> int:
        message = self._receive()
        if message is None:
            return 0
        seq, _, size = message
        filename, _, source = self.slot.request_payload(size).partition(b"\0")
        watch = ReferenceWatch()
        self.filename = filename.decode()
        try:
            instance = self._load(filename.decode(), source.decode("utf-8", errors="replace"), class_name)
        except BaseException as exc:  # noqa: BLE001 - even sys.exit() at import is a load error
            if isinstance(exc, LookupError):
                self._send(seq, b"e", str(exc.args[0]).encode())
            else:
                self._send(seq, b"e", f"importing {filename.decode()} failed: {type(exc).__name__}: {exc}".encode())
            return 1
        has = [callable(getattr(instance, name, None)) for name in ("start", "stop")]
        watch.loading = False
        self._send(seq, b"k", bytes(has) + watch.seen[: wire.MAX_TEXT - 2].encode("utf-8", "replace"))
        while (message := self._receive()) is not None:
            seq, op, size = message
            try:
                if op == b"S":
                    self._step(instance, seq)
                else:
                    self._send(seq, *self._handle(instance, op, self.slot.request_payload(size)))
            except BaseException as exc:  # noqa: BLE001 - reported; the parent decides
                self._error(seq, exc)
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

    def _step(self, instance, seq: int) -> None:
        """One step: the inputs copied out of the slot (the student's code keeps no view of it)."""
        request = self.slot.step_in
        raw = instance.step(
            request[:6].copy(),  # copies: nothing the student's code holds is a view of the slot
            request[6:22].reshape(4, 4).copy(),
            wire.params_from_floats(request[22:-1].tolist()),
            float(request[-1]),
        )
        try:
            twist = np.asarray(raw, dtype=np.float64)
        except (TypeError, ValueError):
            raise TypeError(f"step returned {type(raw).__name__}, not 6 numbers") from None
        if twist.shape != (6,):
            raise ValueError(f"step returned shape {twist.shape}, expected (6,) = [vx, vy, vz, wx, wy, wz]")
        self.slot.twist_out[:] = twist
        wire.HEADER.pack_into(self.slot.memory, wire.ANSWER_AT, seq, b"k", wire.TWIST_BYTES)
        os.write(self.answer_fd, b"\1")

    @staticmethod
    def _handle(instance, op: bytes, payload: bytes) -> tuple[bytes, bytes]:
        if op == b"R":
            instance.reset()
            return b"k", b""
        values = struct.unpack(f"<{len(payload) // 8}d", payload)
        params = wire.params_from_floats(values[: len(wire.PARAM_FIELDS)])
        message = instance.start(params, float(values[-1])) if op == b"A" else instance.stop(params)
        return b"p", np.asarray(wire.params_to_floats(params), float).tobytes() + str(message)[: wire.MAX_TEXT].encode(
            "utf-8", "replace"
        )
