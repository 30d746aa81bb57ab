"""A file that tries to carry state from one graded item to the next (tests/test_sandbox.py): at
import it looks for what an earlier item left; at reset() it leaves all of it for the next. Each step
returns what it found: twist = [module global, file in /tmp, process, System V segment, POSIX
queue, a POSIX queue made now]; all zeros when every item starts clean."""

import ctypes
import os
import time

import numpy as np

import sim.controllers.interface as interface
from sim.controllers.sp import SPController

LIBC = ctypes.CDLL(None, use_errno=True)
MARK = "/tmp/an-earlier-item-was-here"
KEY = 0x5EED


def _found() -> list[float]:
    own = os.getpid()
    others = [p for p in os.listdir("/proc") if p.isdigit() and int(p) not in (1, own, os.getppid())]
    with open("/proc/sysvipc/shm") as handle:
        segments = handle.read().splitlines()[1:]
    return [
        float(getattr(interface, "_an_earlier_item", False)),
        float(os.path.exists(MARK)),
        float(bool(others)),
        float(bool(segments)),
        float(LIBC.mq_open(b"/an-earlier-item", os.O_RDWR, 0o600, None) >= 0),  # a queue an earlier item made
    ]


def _leave() -> float:
    interface._an_earlier_item = True  # a module the zygote imported before the fork
    with open(MARK, "w") as handle:
        handle.write("state")
    LIBC.shmget(KEY, 4096, 0o1000 | 0o600)  # IPC_CREAT: a segment outlives its process
    if os.fork() == 0:  # a process that outlives the item: double fork, the orphan sleeps on
        if os.fork() == 0:
            time.sleep(600)
        os._exit(0)
    os.wait()
    queue = LIBC.mq_open(b"/an-earlier-item", os.O_CREAT | os.O_RDWR, 0o600, None)
    return float(queue >= 0)


MADE = float(LIBC.mq_open(b"/made-at-import", os.O_CREAT | os.O_RDWR, 0o600, None) >= 0)  # none can be made
FOUND = _found()  # at import; what it leaves, at reset() (a process started at import is a load error, in a
# step a fault at the next look: reset() is not watched, so the item lives on with what it left)


class CooperativeLifting(SPController):
    def reset(self):
        super().reset()
        if getattr(self, "loaded", False) and not hasattr(self, "queue"):
            self.queue = _leave()
        self.loaded = True  # the constructor's reset() is part of the load

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        return np.array([*FOUND, MADE])
