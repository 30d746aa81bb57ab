"""A warm start for the suite's labs and its grading commands: `hri-lab serve` (and `grade`,
`experiment`, ...) forked from a process that has imported the server, the grading and the
simulation and warmed the compiled kernels once, as a forkserver does, instead of a new interpreter
importing them for every lab or grade (what it saves: tests/README.md, "Servers").

After the fork the process runs `hri-lab`'s own `main([COMMAND, ...])` with the test's environment,
working folder and output: the same code as `python -m app.cli COMMAND` runs once its imports are
done. What a test of the command's own start needs (its refusals before the imports, its import
time) starts the command itself (`app.serving.launch.ServerProcess`, `tests/e2e/test_cli_server.py`).

One zygote per pytest process, started at its first lab or command and stopped at the session's end
(tests/conftest.py). Each process is forked twice (the zygote's child forks it and exits), so it is
adopted by the test run, the subreaper of its descendants (tests/conftest.py): the test waits for it
and reads its exit status as for any child (`ForkedLab`). A lab writes its output and errors to one
pipe (as `ServerProcess` reads them); a command (`run_command`) to two, read as `subprocess.run` does.

    python -m tests.lab_zygote FD      # FD: the socket the requests come on (one JSON line and its descriptors each)
"""

from __future__ import annotations

import contextlib
import ctypes
import json
import os
import signal
import socket
import subprocess
import sys
import threading
import time
import traceback
from pathlib import Path
from typing import IO

from app.serving.launch import ServerProcess, wait_or_kill

PR_SET_PDEATHSIG = 1
CHECKOUT = Path(__file__).resolve().parents[1]  # where `python -m tests.lab_zygote` is found


class ForkedLab:
    """The part of `subprocess.Popen` a test uses, for a lab the test run adopted (its child)."""

    def __init__(self, pid: int, stdout: IO[str] | None, args: list[str]) -> None:
        self.pid, self.stdout, self.args = pid, stdout, args
        self.returncode: int | None = None

    def _reaped(self, flags: int) -> int | None:
        if self.returncode is None:
            try:
                pid, status = os.waitpid(self.pid, flags)
            except ChildProcessError:  # reaped elsewhere (the run's own check at its end)
                self.returncode = -signal.SIGKILL
                return self.returncode
            if pid:
                self.returncode = os.waitstatus_to_exitcode(status)
        return self.returncode

    def poll(self) -> int | None:
        return self._reaped(os.WNOHANG)

    def wait(self, timeout: float | None = None) -> int:
        deadline = None if timeout is None else time.monotonic() + timeout
        while self.poll() is None:
            if deadline is not None and time.monotonic() > deadline:
                raise subprocess.TimeoutExpired(self.args, timeout or 0.0)
            time.sleep(0.01)
        assert self.returncode is not None
        return self.returncode

    def send_signal(self, sig: int) -> None:
        if self.poll() is None:
            os.kill(self.pid, sig)

    def terminate(self) -> None:
        self.send_signal(signal.SIGTERM)

    def kill(self) -> None:
        self.send_signal(signal.SIGKILL)


def _parent(pid: int) -> int:
    with open(f"/proc/{pid}/stat") as stat:
        return int(stat.read().rsplit(")", 1)[1].split()[1])


class Zygote:
    """The worker's side: the zygote process and the socket its requests go on."""

    def __init__(self) -> None:
        ours, theirs = socket.socketpair()
        self.process = subprocess.Popen(
            [sys.executable, "-m", "tests.lab_zygote", str(theirs.fileno())],
            pass_fds=[theirs.fileno()],
            stdin=subprocess.DEVNULL,
            cwd=CHECKOUT,  # `-m tests...` from the checkout, whatever folder the test that needs it is in
        )
        theirs.close()
        self._socket, self._lock = ours, threading.Lock()
        self._answers = ours.makefile("r")

    def fork(
        self,
        arguments: list[str],
        own_session: bool,
        outputs: list[int] | None = None,
        env: dict[str, str] | None = None,
        cwd: str | None = None,
    ) -> ForkedLab:
        """`hri-lab ARGUMENTS` forked, with this process's environment and working folder (or `env`,
        `cwd`); its output and errors to one new pipe (`ForkedLab.stdout`), or to `outputs`' two
        descriptors (its stdout, its stderr), which this call closes on its side."""
        read = None
        if outputs is None:
            read, write = os.pipe()
            outputs = [write]
        request = {
            "argv": arguments,
            "env": dict(os.environ) if env is None else env,
            "cwd": cwd or os.getcwd(),
            "session": own_session,
        }
        with self._lock:
            try:
                socket.send_fds(self._socket, [json.dumps(request).encode() + b"\n"], outputs)
            finally:
                for fd in outputs:
                    os.close(fd)
            answer = self._answers.readline()
        if not answer:
            if read is not None:
                os.close(read)
            raise RuntimeError(f"the labs' zygote has ended (status {self.process.poll()})")
        lab = ForkedLab(int(answer), os.fdopen(read, "r") if read is not None else None, ["hri-lab", *arguments])
        if _parent(lab.pid) != os.getpid():  # not adopted: nobody here could wait for it
            os.kill(lab.pid, signal.SIGKILL)
            raise RuntimeError("a forked lab is adopted only by a subreaper: tests/conftest.py makes the test run one")
        return lab

    def close(self) -> None:
        """The zygote ends at the end of its requests: the socket closed for good (its file object
        too, which holds the descriptor open while it lives)."""
        with contextlib.suppress(OSError):  # the zygote already gone
            self._socket.shutdown(socket.SHUT_RDWR)
        self._answers.close()
        self._socket.close()
        wait_or_kill(self.process, 10.0)


_zygote: Zygote | None = None


def zygote() -> Zygote:
    global _zygote
    if _zygote is None or _zygote.process.poll() is not None:
        _zygote = Zygote()
    return _zygote


def close() -> None:
    """The zygote stopped, if this process started one (the session's end)."""
    global _zygote
    if _zygote is not None:
        _zygote.close()
        _zygote = None


def run_command(
    *arguments: str, timeout: float, cwd: str | os.PathLike | None = None, env: dict[str, str] | None = None
) -> subprocess.CompletedProcess:
    """`python -m app.cli ARGUMENTS` as `subprocess.run(..., capture_output=True, text=True,
    timeout=timeout)` runs it (its stdout and stderr apart, its exit status; killed and
    TimeoutExpired past the bound), forked from the zygote."""
    (out_read, out_write), (err_read, err_write) = os.pipe(), os.pipe()
    try:
        command = zygote().fork(list(arguments), False, [out_write, err_write], env, None if cwd is None else str(cwd))
    except BaseException:
        os.close(out_read)
        os.close(err_read)
        raise
    texts: dict[int, str] = {}

    def drain(fd: int) -> None:
        with os.fdopen(fd, "r", errors="replace") as stream:
            texts[fd] = stream.read()

    readers = [threading.Thread(target=drain, args=(fd,), daemon=True) for fd in (out_read, err_read)]
    for reader in readers:
        reader.start()
    try:
        code = command.wait(timeout)
    except subprocess.TimeoutExpired:
        command.kill()
        command.wait()
        raise
    finally:
        for reader in readers:
            reader.join(timeout=10)  # the rest of its output (a grandchild holding the pipe: what came so far)
    argv = [sys.executable, "-m", "app.cli", *arguments]
    return subprocess.CompletedProcess(argv, code, texts.get(out_read, ""), texts.get(err_read, ""))


class ForkedServer(ServerProcess):
    """`ServerProcess` whose lab is forked from the zygote."""

    def _start(self, arguments: list[str], own_session: bool) -> ForkedLab:
        return zygote().fork(arguments, own_session)


# --- the zygote's side ---------------------------------------------------------------------------
def _lab(request: dict, outputs: list[int]) -> None:
    """In the forked lab or command: the test's output (one descriptor for both streams, or one
    each), session, folder and environment; then `hri-lab`."""
    os.dup2(outputs[0], 1)
    os.dup2(outputs[-1], 2)
    for fd in outputs:
        os.close(fd)
    if request["session"]:
        os.setsid()
    os.chdir(request["cwd"])
    from app.runtime.process import name_this_process  # the server's: imported by the zygote's warm-up

    name_this_process(request["argv"][0] if request["argv"] else "hri-lab")  # `ps` and bench.suite_time tell it
    os.environ.clear()
    os.environ.update(request["env"])
    sys.argv = ["hri-lab", *request["argv"]]
    code = 1
    try:
        from app.cli.main import main

        code = main(request["argv"])
    except SystemExit as stop:
        code = stop.code if isinstance(stop.code, int) else 1
    except BaseException:  # noqa: BLE001 - a forked lab never returns into the zygote's loop: it ends here
        traceback.print_exc()
    finally:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code or 0)


def _serve(requests: socket.socket) -> None:
    answers = requests.makefile("w")
    pending, fds = b"", []
    while True:
        message, received, _, _ = socket.recv_fds(requests, 1 << 20, 2)
        if not message:
            return
        pending, fds = pending + message, fds + received
        if not pending.endswith(b"\n"):  # a request larger than one read: the rest comes next
            continue
        request, pending = json.loads(pending), b""
        told, tell = os.pipe()
        middle = os.fork()
        if middle == 0:  # forks the lab and ends: the lab is adopted by the test run
            answers.close()
            requests.close()
            os.close(told)
            lab = os.fork()
            if lab == 0:
                os.close(tell)
                _lab(request, fds)
            os.write(tell, str(lab).encode())
            os._exit(0)
        os.close(tell)
        for fd in fds:
            os.close(fd)
        fds = []
        os.waitpid(middle, 0)
        with os.fdopen(told) as pid:
            answers.write(pid.read() + "\n")
        answers.flush()


def _warm() -> None:
    """What every lab's start would do first: import the server and the worlds, load the kernels;
    and what a grade or an experiment imports."""
    from sim.warm_up import warm_up

    import app.cli.experiment
    import app.cli.grade
    import app.cli.main
    import app.cli.serve
    import app.serving.serve
    import app.serving.worlds  # noqa: F401 - imported for what they import: the commands, the server, both worlds

    warm_up()  # every kernel loaded from numba's cache (make test's set-up compiled them)


if __name__ == "__main__":
    ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)  # dies with its test run
    _warm()
    _serve(socket.socket(fileno=int(sys.argv[1])))
