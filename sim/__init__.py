"""hri-lab simulation: a kinematic Franka Panda with a contact plate, a box, a virtual human.

numpy, numba and pinocchio; never imports the server (app/), fastapi or viser.
"""

from sim.kernel_cache import drop_stale_caches

drop_stale_caches()  # before any kernel loads its cache (sim/kernel_cache.py)
