"""Plug-ins that misbehave (load as faults.py:ClassName): each must cost the items it breaks,
never the grader, the server or the loop's rate."""

import os
import socket
import threading
import time

import numpy as np

from sim.controllers.sp import SPController


class SleepsForever(SPController):
    """A step that hangs (far beyond the step timeout)."""

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        time.sleep(600)


class Sleeps50ms(SPController):
    """Each step sleeps 50 ms: no CPU used, but the 1 kHz loop would fall to 20 Hz."""

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        time.sleep(0.05)
        return super().step(wrench_ee, transform_ee_to_base, params, dt)


class StartsThread(SPController):
    """Starts a busy thread at the first step."""

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        if not hasattr(self, "thread"):
            self.thread = threading.Thread(target=lambda: [None for _ in iter(int, 1)], daemon=True)
            self.thread.start()
        return super().step(wrench_ee, transform_ee_to_base, params, dt)


class Forks(SPController):
    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        if not hasattr(self, "child"):
            self.child = os.fork()
            if self.child == 0:
                time.sleep(600)
                os._exit(0)
        return super().step(wrench_ee, transform_ee_to_base, params, dt)


class MemoryBomb(SPController):
    """Keeps 1 MB more at every step."""

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        self.__dict__.setdefault("hoard", []).append(np.ones(1 << 17))
        return super().step(wrench_ee, transform_ee_to_base, params, dt)


class ExitsInStep(SPController):
    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        os._exit(0)


class ReadsSecrets(SPController):
    """Tries to read the grader's files and open a listening socket; reports what it got."""

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        found = []
        for path in ("/etc/passwd", os.path.expanduser("~/.bash_history"), __file__):
            try:
                with open(path) as handle:
                    found.append(f"{path}: {handle.read(40)!r}")
            except OSError as exc:
                found.append(f"{path}: {type(exc).__name__}")
        try:
            server = socket.socket()
            server.bind(("0.0.0.0", 8765))
            server.listen()
            found.append("listening on 8765")
        except OSError as exc:
            found.append(f"socket: {type(exc).__name__}")
        try:
            socket.create_connection(("1.1.1.1", 80), timeout=1)
            found.append("connected out")
        except OSError as exc:
            found.append(f"connect: {type(exc).__name__}")
        raise RuntimeError(" | ".join(found))


class ReachesTheWorld(SPController):
    """Walks up the call stack to the World and marks the person done (what a cheat would do)."""

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        import sys

        frame = sys._getframe()
        while frame is not None:
            world = frame.f_locals.get("self")
            if type(world).__name__ == "World":
                world.human.phase = "done"
            frame = frame.f_back
        return np.zeros(6)


class ShrinksTheSlot(SPController):
    """Tries to shrink the shared slot (fd 5) under its parent: the parent would die of SIGBUS."""

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        os.ftruncate(5, 0)
        return super().step(wrench_ee, transform_ee_to_base, params, dt)


class AnswersEarly(SPController):
    """Before each answer, puts a stale answer (the previous request's number, a NaN twist) in the
    slot and wakes its parent: the parent must wait for the answer to its own request."""

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        import mmap
        import struct

        slot = mmap.mmap(5, os.fstat(5).st_size)
        seq = struct.unpack_from("<Q", slot, 0)[0]
        answer_at = os.fstat(5).st_size - (64 << 10)
        slot[answer_at : answer_at + 48] = struct.pack("<6d", *[float("nan")] * 6)
        struct.pack_into("<QcI", slot, 64, seq - 1, b"k", 48)
        os.write(4, b"\1")
        time.sleep(0.002)  # the parent wakes and sees the stale answer meanwhile
        return super().step(wrench_ee, transform_ee_to_base, params, dt)


class SleepsNowAndThen(SPController):
    """Sleeps 2 s on 10 of every 250 steps: within the count of sleeps a step may take (max_sleeps),
    and no CPU used; only the wall time tells (the issue's `sleeper.py`)."""

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        self.count = getattr(self, "count", 0) + 1
        if self.count % 250 < 10:
            time.sleep(2.0)
        return super().step(wrench_ee, transform_ee_to_base, params, dt)


class OpensFiles(SPController):
    """Opens descriptors without end: files, pipes, sockets (a pair each), memory files."""

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        kept = self.__dict__.setdefault("kept", [])
        for _ in range(100):
            kept.append(open(os.devnull))  # noqa: SIM115 - the file stays open beyond this block (closed by its owner, or held on purpose)
            kept.extend(os.pipe())
            kept.extend(socket.socketpair())
            kept.append(os.memfd_create("x"))
        return super().step(wrench_ee, transform_ee_to_base, params, dt)


class SetsHugeBand(SPController):
    """start() writes forces no parameter set would be allowed (the issue's: /lifting_state showed
    f_n_min 1.7e+308, f_n_max null)."""

    def start(self, params, force):
        params.f_n_min = 1.7e308
        params.f_n_band = 1.7e308
        params.running = True
        return "started"
