"""Worker pools for headless trials that never outlive the process that started them.

Every pool's workers ask Linux to kill them when their parent dies (prctl PR_SET_PDEATHSIG), so a
killed server, CLI or test leaves no trial running behind it.
"""

from __future__ import annotations

import ctypes
import os
import signal
import sys
from concurrent.futures import ProcessPoolExecutor

PR_SET_PDEATHSIG = 1  # linux/prctl.h


def die_with_parent(parent_pid: int) -> None:
    """Pool initializer: SIGKILL this worker when its parent dies; exit now if it already has."""
    if sys.platform.startswith("linux"):
        libc = ctypes.CDLL(None, use_errno=True)
        if libc.prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0) != 0:
            raise OSError(ctypes.get_errno(), "prctl(PR_SET_PDEATHSIG) failed")
    if os.getppid() != parent_pid:  # the parent died before prctl took effect
        os._exit(1)


def worker_pool(jobs: int, mp_context=None) -> ProcessPoolExecutor:
    """A ProcessPoolExecutor of `jobs` workers that die with this process."""
    return ProcessPoolExecutor(
        max_workers=max(1, jobs), mp_context=mp_context, initializer=die_with_parent, initargs=(os.getpid(),)
    )
