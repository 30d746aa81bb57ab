"""The issue's `sleeper.py`: step() sleeps 2 s on 10 of every 250 steps. It stays within the count
of sleeps a step may take (max_sleeps in check_every steps) and uses no CPU: neither RLIMIT_CPU nor
the CPU budget sees it; a grade of it printed nothing after 300 s."""

import time

import numpy as np


class CooperativeLifting:
    def reset(self):
        self.count = 0

    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        self.count = getattr(self, "count", 0) + 1
        if self.count % 250 < 10:
            time.sleep(2.0)
        return np.zeros(6)
