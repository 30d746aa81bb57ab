"""The parent's end of the zygotes (zygote.py): a jail whose first process has imported what a
child needs and forks a fresh child for each controller (each graded item), one child at a time.

A jail belongs to the process and the thread that started it (bubblewrap dies with that thread:
`--die-with-parent`; a later thread never takes it, even with the same ident), for one class and
one budget's limits. When its child has ended, the jail
waits IDLE_SECONDS for the next item of the same file, then it is ended; whatever is left when the
process exits is ended too. So a grade starts one jail per worker, not one per item, and leaves
no process behind.
"""

from __future__ import annotations

import fcntl
import itertools
import multiprocessing.util
import os
import select
import signal
import socket
import threading
import time

from sim.controllers.sandbox import watch, zygote
from sim.controllers.sandbox.budget import SandboxBudget
from sim.controllers.sandbox.jail import CHILD_ENV, bwrap_command, zygote_command

IDLE_SECONDS = 2.0  # s an idle jail waits for the next item before it is ended


class JailError(Exception):
    """The jail cannot start or answer (the message says why)."""


class Jail:
    """One jail and its zygote; `fork()` starts a child for one item, `end_item()` ends it."""

    def __init__(self, key: tuple, budget: SandboxBudget, class_name: str, sandboxed: bool) -> None:
        self.key, self.owner = key, os.getpid()
        self.item: int | None = None  # the item's child (its pid in the jail) while it runs
        self.timer: threading.Timer | None = None
        argv = zygote_command(budget, class_name, jailed=sandboxed)
        if sandboxed:
            argv = bwrap_command(argv, budget.tmp_bytes)
        ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        errors_r, errors_w = os.pipe()
        control_fd, errors_w = _above(theirs.detach(), zygote.CONTROL_FD), _above(errors_w, zygote.CONTROL_FD)
        try:
            self.pid = os.posix_spawn(
                argv[0],
                argv,
                CHILD_ENV if sandboxed else {**os.environ, **CHILD_ENV},
                file_actions=[
                    (os.POSIX_SPAWN_OPEN, 0, os.devnull, os.O_RDONLY, 0),
                    (os.POSIX_SPAWN_OPEN, 1, os.devnull, os.O_WRONLY, 0),
                    (os.POSIX_SPAWN_DUP2, errors_w, 2),
                    (os.POSIX_SPAWN_DUP2, control_fd, zygote.CONTROL_FD),
                ],
                setsid=True,
                scheduler=(os.SCHED_OTHER, os.sched_param(0)),  # never the live loop's SCHED_FIFO
            )
        except OSError as exc:
            os.close(errors_r)
            ours.close()
            raise JailError(f"cannot start the controller's process: {exc}") from None
        finally:
            for fd in (control_fd, errors_w):
                try:
                    os.close(fd)
                except OSError:
                    pass
        self.control, self.errors = ours, errors_r
        os.set_blocking(errors_r, False)
        self._poll = select.poll()
        self._poll.register(ours, select.POLLIN)
        ready = self._receive(time.monotonic() + budget.load_timeout)
        if ready != b"R":
            said = self.said()
            self.close()
            raise JailError(
                f"the controller's process did not start: {'no answer in time' if ready is None else 'it ended'}"
                + (f"; it said: {said}" if said else "")
            )
        self.infra = set(watch.process_tree(self.pid))  # bwrap, its init, the zygote: what no item is

    def _receive(self, deadline: float) -> bytes | None:
        """The zygote's next message; b"" when it is gone, None at the deadline."""
        while True:
            left = deadline - time.monotonic()
            if left <= 0 or not self._poll.poll(left * 1e3 + 1):
                return None
            try:
                return self.control.recv(64)
            except BlockingIOError:
                continue
            except OSError:
                return b""

    def said(self) -> str:
        try:
            return os.read(self.errors, 4000).decode("utf-8", "replace").strip()
        except OSError:
            return ""

    def alive(self) -> bool:
        try:
            done, _ = os.waitpid(self.pid, os.WNOHANG)
        except ChildProcessError:
            return False
        return done == 0 and not self._poll.poll(0)  # no message pending, no hang-up

    def fork(self, fds: list[int], timeout: float) -> int:
        """A fresh child for one item with these descriptors (zygote.py: slot, wake-up, answer, stderr); its pid in the jail."""
        try:
            socket.send_fds(self.control, [b"F"], fds)
        except OSError as exc:
            raise JailError(f"the controller's jail is gone: {exc}") from None
        message = self._receive(time.monotonic() + timeout)
        if not message or message[:1] != b"P":
            raise JailError("the controller's jail did not start its process")
        (self.item,) = zygote.STARTED.unpack(message[1:])
        return self.item

    def item_tree(self) -> list[int]:
        """The item's processes (this process's pids): everything in the jail but bwrap and the zygote."""
        return [pid for pid in watch.process_tree(self.pid) if pid not in self.infra]

    def end_item(self, grace: float) -> int | None:
        """Wait up to `grace` s for the item's child to end (its input is closed), then kill the
        item's processes; the child's wait status (None: the jail went with it)."""
        if self.item is None:
            return None
        deadline, killed = time.monotonic() + grace, False
        while True:
            message = self._receive(deadline)
            if message and message[:1] == b"X":
                pid, status = zygote.ENDED.unpack(message[1:])
                if pid == self.item:
                    break
            elif message == b"" or (message is None and killed):
                self.close()  # the zygote is gone or stuck: the whole jail goes
                return None
            elif message is None:
                self._kill_item()
                killed, deadline = True, time.monotonic() + 5.0
        self._kill_item()  # what the child left behind (orphans in the jail)
        self.item = None
        return status

    def _kill_item(self) -> None:
        for pid in self.item_tree():
            try:
                os.kill(pid, signal.SIGKILL)
            except OSError:
                pass

    def close(self) -> None:
        """End the jail: the zygote's input closed, then SIGKILL to its process group if it lingers."""
        if self.timer is not None:
            self.timer.cancel()
        if self.control.fileno() >= 0:
            self.control.close()
            try:
                os.close(self.errors)
            except OSError:
                pass
        if self.owner == os.getpid():
            watch.reap(self.pid, grace=0.5)
        self.item = None


_idle: dict[tuple, list[Jail]] = {}
_every: list[Jail] = []  # every jail this process started and has not ended
_lock = threading.Lock()
_local = threading.local()
_tokens = itertools.count(1)


def fork(budget: SandboxBudget, class_name: str, sandboxed: bool, fds: list[int]) -> tuple[Jail, int]:
    """A fresh child for one item (fds: Jail.fork's), forked by an idle jail of this process and
    thread for this class and these limits, or by a new one; (its jail, its pid in the jail)."""
    jail, fresh = take(budget, class_name, sandboxed)
    try:
        return jail, jail.fork(fds, budget.load_timeout)
    except JailError:
        _end(jail)
        if fresh:
            raise
    jail, _ = take(budget, class_name, sandboxed)  # the idle one went meanwhile: once more, a new one
    try:
        return jail, jail.fork(fds, budget.load_timeout)
    except JailError:
        _end(jail)
        raise


def _thread_token() -> int:
    """This thread's own number (a thread's ident may be reused by a later thread; this is not)."""
    token = getattr(_local, "token", None)
    if token is None:
        token = _local.token = next(_tokens)
    return token


def take(budget: SandboxBudget, class_name: str, sandboxed: bool) -> tuple[Jail, bool]:
    """An idle jail of this process and thread for this class and these limits, or a new one; (it, new)."""
    key = (os.getpid(), _thread_token(), class_name, sandboxed, budget)
    while True:
        with _lock:
            jail = _idle.get(key, []).pop() if _idle.get(key) else None
            if jail is not None and jail.timer is not None:
                jail.timer.cancel()
                jail.timer = None
        if jail is None:
            break
        if jail.alive():
            return jail, False
        _end(jail)
    jail = Jail(key, budget, class_name, sandboxed)
    with _lock:
        _every.append(jail)
        if _at_exit[0] != os.getpid():  # once per process: a pool's worker starts with no finalizer
            _at_exit[0] = os.getpid()
            multiprocessing.util.Finalize(None, close_all, exitpriority=100)
    return jail, True


def give_back(jail: Jail) -> None:
    """The jail's item has ended: kept IDLE_SECONDS for the next one (if it is well), then ended."""
    if jail.owner != os.getpid() or jail.item is not None or not jail.alive():
        _end(jail)
        return
    with _lock:
        _idle.setdefault(jail.key, []).append(jail)
        jail.timer = threading.Timer(IDLE_SECONDS, _expire, (jail,))
        jail.timer.daemon = True
        jail.timer.start()


def _expire(jail: Jail) -> None:
    with _lock:
        idle = _idle.get(jail.key, [])
        if jail not in idle:
            return  # taken meanwhile
        idle.remove(jail)
    _end(jail)


def _end(jail: Jail) -> None:
    with _lock:
        if jail in _every:
            _every.remove(jail)
    jail.close()


def close_all() -> None:
    """End every jail of this process (idle or not): at exit, and when a caller wants none left."""
    with _lock:
        jails = [jail for jail in _every if jail.owner == os.getpid()]
        _idle.clear()
    for jail in jails:
        _end(jail)


def _forget() -> None:
    """In a forked child: the parent's jails are not ours (a lock held at the fork is not either)."""
    global _lock
    _lock = threading.Lock()
    _idle.clear()
    _every.clear()


os.register_at_fork(after_in_child=_forget)
# close_all at exit (multiprocessing's finalizers run at a pool worker's exit and, through atexit,
# at any process's): registered by the first jail of each process, since a worker clears the
# finalizers it inherited; ended jails are waited for, so their CPU is counted (getrusage)
_at_exit = [0]  # the process that registered it


def _above(fd: int, highest: int) -> int:
    """fd moved to a number above `highest` (close-on-exec; posix_spawn's dup2 clears it on the copy)."""
    if fd > highest:
        return fd
    moved = fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, highest + 1)
    os.close(fd)
    return moved
