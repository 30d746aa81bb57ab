"""Worker processes of the server's actions (experiment, comparison) that die with the server,
however it dies (SIGKILL included): each sets PR_SET_PDEATHSIG (Linux) before it runs, so the
kernel kills it when the server goes; spawned, never forked from the server's threads."""
import ctypes
import multiprocessing.context
import os
import signal
import sys

PR_SET_PDEATHSIG = 1


def die_with_parent(parent_pid: int) -> None:
    """SIGKILL this process when its parent dies; exit now if the parent is already gone."""
    if sys.platform.startswith("linux"):
        ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    if os.getppid() != parent_pid:
        os._exit(1)


class WorkerProcess(multiprocessing.context.SpawnProcess):
    def run(self) -> None:
        die_with_parent(self._parent_pid)
        super().run()


class WorkerContext(multiprocessing.context.SpawnContext):
    """mp_context of the action pools: spawned workers that die with the server."""

    Process = WorkerProcess


WORKERS = WorkerContext()
