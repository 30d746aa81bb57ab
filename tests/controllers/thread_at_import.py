"""A file that starts a thread and a process while it is imported (before any step is watched)."""

import os
import threading
import time

import numpy as np

threading.Thread(target=time.sleep, args=(600,), daemon=True).start()
if os.fork() == 0:
    time.sleep(600)
    os._exit(0)


class CooperativeLifting:
    def reset(self):
        pass

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        return np.zeros(6)
