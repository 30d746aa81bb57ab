"""A file that writes all it can at import (docs/operations.md, the attack suite): 100 files of
15 MiB into /tmp, then into every other place that might be writable (/dev/shm, /var/tmp, /run,
$HOME and the working folder unless they are /tmp, /dev), and as many anonymous memory files (memfd) as it can hold open.
Each step returns what was written, in MiB: twist = [/tmp, every other place, memfds, 0, 0, 0]."""

import os

import numpy as np

CHUNK = b"\0" * (1 << 20)
MIB = 1 << 20


def _fill(path: str, files: int = 100, mib: int = 15) -> int:
    """Bytes written under `path` (files of up to `mib` MiB each, each until a write fails)."""
    written = 0
    for index in range(files):
        try:
            handle = open(os.path.join(path, f"filler-{index}"), "wb", buffering=0)  # noqa: SIM115 - the file stays open beyond this block (closed by its owner, or held on purpose)
        except OSError:  # read-only, or not there
            break
        with handle:
            try:
                for _ in range(mib):
                    written += handle.write(CHUNK) or 0
            except OSError:  # full, or the file-size limit
                pass
    return written


def _memfds(count: int = 100, mib: int = 15) -> int:
    """Bytes written into anonymous memory files kept open (no path: no file system counts them)."""
    written, kept = 0, []
    for _ in range(count):
        try:
            fd = os.memfd_create("filler")
        except OSError:
            break
        kept.append(fd)
        try:
            for _ in range(mib):
                written += os.write(fd, CHUNK)
        except OSError:
            pass
    return written


IN_TMP = _fill("/tmp")
OTHERS = {os.path.realpath(p) for p in ("/dev/shm", "/var/tmp", "/run", os.path.expanduser("~"), os.getcwd(), "/dev")}
ELSEWHERE = sum(_fill(path) for path in sorted(OTHERS - {"/tmp"}))
IN_MEMFDS = _memfds()


class CooperativeLifting:
    def reset(self):
        pass

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        return np.array([IN_TMP / MIB, ELSEWHERE / MIB, IN_MEMFDS / MIB, 0.0, 0.0, 0.0])
