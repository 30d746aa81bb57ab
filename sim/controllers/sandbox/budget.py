"""What a sandboxed controller may use (sim/controllers/sandbox/parent.py enforces it)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class SandboxBudget:
    """What a sandboxed controller may use (SI units)."""

    step_timeout: float = 10.0  # s wall for one answer: beyond it the child is hung (generous: a loaded machine stalls)
    load_timeout: float = 60.0  # s wall to start Python and import the file (a loaded machine is slow)
    max_sleeps: int = 10  # times step() may sleep or block (voluntary context switches) within `check_every` steps
    mean_cpu: float = 0.5e-3  # s per step, CPU of all the child's threads, over `window` steps
    window: int = 1000  # steps
    slow_step: float = 0.02  # s wall: a step this slow makes us look now
    check_every: int = 250  # steps between looks at the child's threads and CPU time (/proc)
    memory_bytes: int = 1 << 30  # RLIMIT_AS
    cpu_seconds: int = 0  # RLIMIT_CPU of one child (0 = none: the live server runs for hours)
    tmp_bytes: int = 64 << 20  # size of the jail's /tmp, its one writable file system (bwrap --size)
    file_bytes: int = 4 << 20  # RLIMIT_FSIZE: one file, /tmp's or an anonymous memory file's (memfd)
    open_files: int = 64  # RLIMIT_NOFILE: descriptors of one child (files, sockets, pipes, memfds)
    sleep_ratio: float = 1.0  # s of wall time step() may spend sleeping per s of simulated time ...
    sleep_grace: float = 2.0  # ... plus this (s): beyond it the item is stopped (parent.py, _account)
    no_schedstat_ratio: float = 20.0  # where /proc has no schedstat: s of step() wall time per simulated s
    file_sleep: float = 10.0  # s a file's items may sleep in all (in one process): beyond it, no more of its items run
