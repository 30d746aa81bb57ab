"""The jail a student's controller runs in: bubblewrap's command line and the child's environment.

`bwrap --unshare-all --cap-drop ALL`: no network, no other process, a read-only view of only what
Python needs (/usr, the interpreter, the virtual environment, the `sim` package), a private /tmp of
SandboxBudget.tmp_bytes;
the child (child.py) sets its own memory and CPU-time limits before the student's code runs.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from functools import cache
from pathlib import Path

import sim
from sim.controllers.sandbox.budget import SandboxBudget

ZYGOTE_MODULE = "sim.controllers.sandbox.zygote"
CHILD_ENV = {
    "PATH": "/usr/bin:/bin",
    "HOME": "/tmp",
    "LANG": "C.UTF-8",
    "PYTHONDONTWRITEBYTECODE": "1",
    "PYTHONHASHSEED": "0",
    "OPENBLAS_NUM_THREADS": "1",
    "OMP_NUM_THREADS": "1",
    "MKL_NUM_THREADS": "1",
    "NUMBA_NUM_THREADS": "1",
}


def _readable_roots() -> list[str]:
    """What the child must see: the interpreter (venv and base), the `sim` package."""

    roots = {sys.prefix, sys.base_prefix, sys.exec_prefix, sys.base_exec_prefix, str(Path(sim.__file__).parent)}
    roots.add(str(Path(sys.executable).resolve().parent.parent))
    return sorted(r for r in roots if not r.startswith("/usr"))


def bwrap_command(
    child: list[str],
    tmp_bytes: int = SandboxBudget.tmp_bytes,
    readable: tuple[str, ...] = (),
    workdir: str = "/tmp",
) -> list[str]:
    """bwrap's command line for `child`; the jail's /tmp holds at most tmp_bytes (a tmpfs is memory:
    RLIMIT_AS does not count it, nor RLIMIT_FSIZE beyond one file). `readable`: more folders it sees,
    read-only (a student's ROS program's own folder, the lab's code its `hri-lab run` imports). No
    network but a loopback of the jail's own (a ROS program reaches its trial's lab through a Unix
    socket in its folder: app/cli/trial_link.py)."""
    bwrap = shutil.which("bwrap") or "bwrap"
    argv = [
        bwrap,
        "--unshare-all",
        "--die-with-parent",
        "--new-session",
        "--cap-drop",
        "ALL",
        "--ro-bind",
        "/usr",
        "/usr",
        "--size",
        str(tmp_bytes),
        "--tmpfs",
        "/tmp",
        "--proc",
        "/proc",
        "--dev",
        "/dev",
    ]
    for top in ("/bin", "/sbin", "/lib", "/lib32", "/lib64"):
        if os.path.islink(top):
            argv += ["--symlink", os.readlink(top), top]
        elif os.path.isdir(top):
            argv += ["--ro-bind", top, top]
    for root in [*_readable_roots(), *readable]:
        argv += ["--ro-bind", root, root]
    # read-only at last: /tmp is the jail's one writable file system (the zygote empties it between
    # items); /dev/shm is a folder of the read-only /dev, /proc's files are the kernel's
    return argv + ["--remount-ro", "/dev", "--remount-ro", "/", "--chdir", workdir, "--"] + child


def zygote_command(budget: SandboxBudget, class_name: str, jailed: bool) -> list[str]:
    """The zygote's command line (zygote.py): its items' limits, the class, whether it is in a jail."""
    return [
        sys.executable,
        "-m",
        ZYGOTE_MODULE,
        str(budget.memory_bytes),
        str(budget.cpu_seconds),
        str(budget.file_bytes),
        str(budget.open_files),
        class_name,
        "1" if jailed else "0",
    ]


@cache
def sandbox_unavailable() -> str | None:
    """None when bubblewrap can run here, else why not (for `hri-lab grade`'s refusal)."""
    if shutil.which("bwrap") is None:
        return "bubblewrap (bwrap) is not installed: `apt-get install bubblewrap` (make test does it)"

    try:
        run = subprocess.run(bwrap_command(["/usr/bin/true"]), capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired) as exc:
        return f"bwrap cannot run: {exc}"
    return None if run.returncode == 0 else f"bwrap cannot run here: {run.stderr.strip() or run.returncode}"
