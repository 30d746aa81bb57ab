"""The compiled step's three compositions step the same world the same way: one compiled call (a
built-in controller), compiled sense + the controller in Python + compiled robot and rest (a subclass of SP
with its own twist_ee), and the rest through the components' Python methods (a patched human)."""

import numpy as np

from sim.controllers.sp import SPController
from sim.person.participants import PARTICIPANTS
from sim.world import World


class SPInPython(SPController):
    def twist_ee(self, wrench_ee, params):
        return super().twist_ee(wrench_ee, params)


def trial_world(controller=None, patch_human=False) -> World:
    world = World(controller=controller or SPController())
    world.reset(PARTICIPANTS["hasty"], seed=3)
    if patch_human:
        world.human.step = world.human.step  # set on the instance: the rest runs through Python methods
    world.start_lifting(10.0)
    return world


def state(world: World) -> np.ndarray:
    return np.concatenate(
        (
            world.arm.q,
            world.box.position,
            world.box.rotation.ravel(),
            world.human.position,
            world.wrench_ee,
            world.twist_command,
            world.plate_out,
            world.palm_out,
        )
    )


def test_the_three_compositions_step_alike():
    compiled, split, python_rest = trial_world(), trial_world(SPInPython()), trial_world(patch_human=True)
    assert compiled.controller.law() is not None
    assert split.controller.law() is None
    assert compiled._components_plain()
    assert not python_rest._components_plain()
    for _ in range(6000):  # the approach, the grip, the release and the start of the carry
        for world in (compiled, split, python_rest):
            world.step()
    assert compiled.human.phase in ("settling", "carrying")
    assert compiled.trial.state == "running"
    np.testing.assert_allclose(state(split), state(compiled), rtol=0, atol=1e-6)
    np.testing.assert_allclose(state(python_rest), state(compiled), rtol=0, atol=1e-6)
    assert split.human.phase == python_rest.human.phase == compiled.human.phase
