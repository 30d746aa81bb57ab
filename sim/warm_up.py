"""Every kernel the lab runs compiled (or loaded from numba's cache) at set-up, as `make .venv/.kernels`
does, so that no first process of a run compiles them (sim/kernel_cache.py keeps the caches true to
the sources). Above the world: it steps one."""

import numpy as np

from sim.controllers.interface import LiftingParams, ZeroController
from sim.controllers.patch import PatchController
from sim.mobile.world import MobileWorld
from sim.world import World


def warm_up() -> None:
    """Compile (or load) every kernel the lab runs, as `make .venv/.kernels` does at set-up: a
    step with each built-in controller, with a controller in Python, a joint motion, with a
    patched component, and the components' own methods."""
    for controller in (None, PatchController(), ZeroController()):
        world = World() if controller is None else World(controller=controller)
        world.start_lifting(10.0)
        world.run(0.005)
        world.move_to_start()
        world.run(0.003)
        world.human.step(1e-3, 0.0, 0.0, 0.0, None, np.eye(3))
        world.human.hand_wrench(world.box.pose(), 1.0)
        world.human.tilted_level()
        world.plate_contact.step(np.eye(3), np.zeros(3), np.zeros(3), np.zeros(3), world.box.pose(), 1e-3)
        world.box.step(np.zeros(3), np.zeros(3), 1e-3)
        world.sensor.measure(np.zeros(6), 1e-3)
        world.arm.command_twist(np.zeros(6), 1e-3)
        world.controller.step(np.zeros(6), np.eye(4), LiftingParams(running=True), 1e-3)
        world.human.step = world.human.step  # type: ignore[method-assign]  # a patched component: the rest through Python methods
        world.run(0.002)
        del world.human.step
    mobile = MobileWorld()  # the mobile world's kernels: the base's step, the scan, the distances
    mobile.drive(0.1, 0.5)
    mobile.run(0.25)
    mobile.nearest_surface()
