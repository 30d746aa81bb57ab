"""The process a student's controller runs in (started by sim/controllers/sandbox.py, inside
bubblewrap). It reads requests on fd 3 and answers on fd 4 (sandbox.py has the message layout).

Before the student's code runs: normal scheduling (never the loop's SCHED_FIFO), resource limits
(memory, CPU time, file size, no real-time priority), one BLAS thread, stdout/stderr discarded.
The student's file arrives as text in the first message: nothing else of the grader's file system
needs to be visible.
    python -m sim.controllers.sandbox_child MEMORY_BYTES CPU_SECONDS CLASS_NAME
"""
from __future__ import annotations

import os
import resource
import sys


def _limit(memory_bytes: int, cpu_seconds: int) -> None:
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


def main(argv: list[str]) -> int:
    memory_bytes, cpu_seconds, class_name = int(argv[0]), int(argv[1]), argv[2]
    _limit(memory_bytes, cpu_seconds)
    from sim.controllers.sandbox import ChildEnd

    return ChildEnd(3, 4).serve(class_name)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
