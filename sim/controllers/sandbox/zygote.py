"""The zygote: the one process a jail starts with (pool.py spawns it through jail.py). It imports
what every item's child needs (numpy, the wire, the controller interface, the lab's SP) and never
runs a student's code; for each graded item it clears the jail and forks a fresh child, which sets
its limits and only then loads the student's file (child.py). The fork comes BEFORE the student's
module is imported: every item imports the file afresh into a copy of a process no student's code
ever ran in, so module globals, threads, handlers or anything an import does cannot reach another
item (forking after the import would run the student's code in the zygote, which lives through
every item and holds the next items' descriptors).

What a jail keeps between its processes is cleared before each fork (only in a jail: `--jailed`):
every other process in the jail's pid namespace is killed (`kill(-1)`: all but bubblewrap's init
and the zygote) and waited for, /tmp is emptied (the jail's only writable file system: jail.py
mounts / and /dev read-only), System V IPC objects are removed, the user keyrings are cleared.
POSIX message queues cannot be listed from here, so an item may create none (RLIMIT_MSGQUEUE 0,
child.py). The zygote is not dumpable: an item cannot ptrace it or read its memory.
    python -m sim.controllers.sandbox.zygote MEMORY_BYTES CPU_SECONDS FILE_BYTES OPEN_FILES CLASS_NAME JAILED

The control socket (SOCK_SEQPACKET) on CONTROL_FD:
    parent -> zygote  b"F" with 4 descriptors (SCM_RIGHTS): the item's slot, its wake-up pipe,
                      its answer pipe, its stderr
    zygote -> parent  b"R" ready; b"P" + pid: the item's child (its pid in the jail);
                      b"X" + pid + wait status: the item's child ended
"""

from __future__ import annotations

import ctypes
import fcntl
import os
import select
import signal
import socket
import struct
import sys
import time

CONTROL_FD = 3
STARTED = struct.Struct("<i")  # after b"P": the item's pid
ENDED = struct.Struct("<ii")  # after b"X": the item's pid, its wait status
ITEM_FDS = 4  # slot, wake-up, answer, stderr
_LIBC = ctypes.CDLL(None, use_errno=True)
_KEYCTL = {"x86_64": 250, "aarch64": 219}  # the keyctl system call's number
KEYCTL_CLEAR, KEYCTL_JOIN_SESSION_KEYRING = 7, 1
KEY_SPEC_USER_KEYRING, KEY_SPEC_USER_SESSION_KEYRING = -4, -5
PR_SET_DUMPABLE = 4


def keyctl(*args: int) -> None:
    """keyctl(2) (there is no wrapper in Python): a failure leaves nothing to clear."""
    number = _KEYCTL.get(os.uname().machine)
    if number is not None:
        _LIBC.syscall(number, *(ctypes.c_long(a) for a in args))


def _wipe(directory: str) -> None:
    """Everything under `directory` removed (what the item made unreadable is made readable first)."""
    try:
        entries = list(os.scandir(directory))
    except OSError:
        return
    for entry in entries:
        try:
            if entry.is_dir(follow_symlinks=False):
                os.chmod(entry.path, 0o700)
                _wipe(entry.path)
                os.rmdir(entry.path)
            else:
                os.unlink(entry.path)
        except OSError:
            pass


def _remove_ipc() -> None:
    """Every System V shared memory segment, semaphore set and message queue of the jail (its own IPC namespace)."""
    for kind, remove in (
        ("shm", lambda i: _LIBC.shmctl(i, 0, None)),
        ("sem", lambda i: _LIBC.semctl(i, 0, 0)),
        ("msg", lambda i: _LIBC.msgctl(i, 0, None)),
    ):
        try:
            with open(f"/proc/sysvipc/{kind}") as handle:
                rows = handle.read().splitlines()[1:]
        except OSError:
            continue
        for row in rows:
            remove(int(row.split()[1]))  # IPC_RMID of the identifier


def _others() -> list[int]:
    """Processes in the jail but bubblewrap's init (1) and this one."""
    own = os.getpid()
    return [int(p) for p in os.listdir("/proc") if p.isdigit() and int(p) not in (1, own)]


def clear_jail(tmp_mode: int, timeout: float = 5.0) -> None:
    """The jail as it was before any item: no other process, an empty /tmp, no IPC object, no key."""
    deadline = time.monotonic() + timeout
    while True:
        try:
            os.kill(-1, signal.SIGKILL)  # every process but init and this one (this is a pid namespace)
        except ProcessLookupError:
            pass
        _reap_all()
        if not _others() or time.monotonic() > deadline:
            break
        time.sleep(0.001)  # orphans are reaped by bubblewrap's init
    os.chmod("/tmp", tmp_mode)
    _wipe("/tmp")
    _remove_ipc()
    keyctl(KEYCTL_CLEAR, KEY_SPEC_USER_KEYRING)
    keyctl(KEYCTL_CLEAR, KEY_SPEC_USER_SESSION_KEYRING)


def _reap_all() -> list[tuple[int, int]]:
    ended: list[tuple[int, int]] = []
    while True:
        try:
            pid, status = os.waitpid(-1, os.WNOHANG)
        except ChildProcessError:
            return ended
        if pid == 0:
            return ended
        ended.append((pid, status))


def _item(fds: list[int], control: socket.socket, limits: tuple[int, int, int, int], class_name: str) -> int:
    """In the forked child: the item's descriptors where child.py expects them, a session keyring
    of its own, limits, then the student's file served (child.py)."""
    from sim.controllers.sandbox import child, wire

    control.close()
    slot, wake, answer, errors = fds
    for fd, number in ((errors, 2), (wake, wire.WAKE_CHILD_FD), (answer, wire.WAKE_PARENT_FD), (slot, wire.SLOT_FD)):
        os.dup2(fd, number)
    os.closerange(wire.SLOT_FD + 1, 1 << 16)
    keyctl(KEYCTL_JOIN_SESSION_KEYRING, 0)  # not the zygote's: the next item gets another
    signal.signal(signal.SIGCHLD, signal.SIG_DFL)
    child.limit(*limits)
    return child.ChildEnd(wire.WAKE_CHILD_FD, wire.WAKE_PARENT_FD, wire.SLOT_FD).serve(class_name)


def serve(limits: tuple[int, int, int, int], class_name: str, jailed: bool) -> int:
    """Fork a child per item (limits: child.limit's memory, CPU time, file size, descriptors)."""
    control = socket.socket(fileno=CONTROL_FD)
    control.send(b"R")
    item, pidfd = 0, -1
    tmp_mode = os.stat("/tmp").st_mode & 0o7777
    poll = select.poll()
    poll.register(control, select.POLLIN)
    while True:
        for fd, _ in poll.poll():
            if fd == pidfd:  # the item's child ended: its status to the parent
                for pid, status in _reap_all():
                    if pid == item:
                        poll.unregister(pidfd)
                        os.close(pidfd)
                        item, pidfd = 0, -1
                        control.send(b"X" + ENDED.pack(pid, status))
                continue
            try:
                message, fds, _, _ = socket.recv_fds(control, 64, ITEM_FDS)
            except OSError:
                return 1
            if not message:  # the parent is done
                return 0
            if message[:1] != b"F" or len(fds) != ITEM_FDS or item:
                for fd in fds:
                    os.close(fd)
                return 1
            high = [fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 16) for fd in fds]  # away from 2-5 before the dup2s
            for fd in fds:
                os.close(fd)
            if jailed:
                clear_jail(tmp_mode)
            pid = os.fork()
            if pid == 0:
                code = 1
                try:
                    code = _item(high, control, limits, class_name)
                finally:
                    os._exit(code)
            for fd in high:
                os.close(fd)
            item, pidfd = pid, os.pidfd_open(pid)
            poll.register(pidfd, select.POLLIN)
            control.send(b"P" + STARTED.pack(pid))


def main(argv: list[str]) -> int:
    memory_bytes, cpu_seconds, file_bytes, open_files = (int(a) for a in argv[:4])
    class_name, jailed = argv[4], argv[5] == "1"
    if jailed and os.getpid() != 2:  # clear_jail kills every process it may: only ever inside bwrap's pid namespace
        print("the zygote is not bubblewrap's child in a pid namespace of its own", file=sys.stderr)
        return 1
    _LIBC.prctl(PR_SET_DUMPABLE, 0, 0, 0, 0)  # no ptrace, no /proc/PID/mem for an item
    if not jailed:
        _LIBC.prctl(1, signal.SIGKILL, 0, 0, 0)  # die with the parent also without bwrap (PR_SET_PDEATHSIG)
    os.sched_setscheduler(0, os.SCHED_OTHER, os.sched_param(0))
    import numpy  # noqa: F401 - what every item's child would import: once, here

    import sim.controllers.interface
    import sim.controllers.sandbox.child

    try:
        import sim.controllers.sp  # noqa: F401 - what a file built on the lab's SP imports
    except ImportError:
        pass
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 1)
    return serve((memory_bytes, cpu_seconds, file_bytes, open_files), class_name, jailed)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
